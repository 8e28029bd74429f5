#!/usr/bin/env bash
# Every fracture pattern on every built-in test mesh at 64, 1024 and 4096
# pieces (planes~: planes with --noise 0.02 --noise-frequency 6): pieces made,
# watertight, leaf volume error, time, sliver fraction.
# The numbers of the patterns section of the README come from this script.
#   scripts/pattern_matrix.sh [BREAKABLES] [COUNTS...]   (default build-r/breakables 64 1024 4096)
set -euo pipefail
bin="${1:-build-r/breakables}"
shift || true
counts=("$@")
[[ ${#counts[@]} -gt 0 ]] || counts=(64 1024 4096)
here="$(cd "$(dirname "$0")/.." && pwd)"
map="$here/assets/maps/cracks.png"
field() { grep -o "\"$1\": [^,}]*" <<<"$2" | head -n 1 | sed 's/.*: //'; }
printf '%-9s %-8s %6s %6s %10s %10s %9s %8s\n' pattern mesh asked made watertight vol_error ms slivers
fail=0
for mesh in cube bunny eggshell torus wall; do
  for pattern in planes planes~ voronoi clustered radial brick cutout; do
    for pieces in "${counts[@]}"; do
      extra=()
      [[ $pattern == cutout ]] && extra=(--cutout "$map")
      # planes~: noisy planes (every built-in mesh is about a metre across)
      [[ $pattern == planes~ ]] && extra=(--noise 0.02 --noise-frequency 6)
      out="$("$bin" fracture --mesh "$mesh" --pattern "${pattern%\~}" --pieces "$pieces" "${extra[@]}" --json 2>/dev/null)" ||
        { printf '%-9s %-8s %6s  FAILED\n' "$pattern" "$mesh" "$pieces"; fail=1; continue; }
      made="$(field pieces_made "$out")"
      tight="$(field watertight "$out")"
      err="$(field volume_rel_error "$out")"
      printf '%-9s %-8s %6s %6s %10s %10s %9s %8s\n' "$pattern" "$mesh" "$pieces" "$made" "$tight" "$err" \
        "$(field ms "$out")" "$(field sliver_fraction "$out")"
      if [[ $tight != true ]] || [[ $pattern != cutout && $made != "$pieces" ]] ||
        ! awk -v e="$err" 'BEGIN { exit !(e < 1e-9) }'; then fail=1; fi
      [[ $pattern == cutout ]] && break # the map decides the pieces
    done
  done
done
exit "$fail"
