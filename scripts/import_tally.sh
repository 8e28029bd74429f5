#!/usr/bin/env bash
# Fractures every model of Debian's assimp-testmodels in a format --mesh
# reads into 16 pieces and tallies the outcomes by format:
#
#   scripts/import_tally.sh [BREAKABLES_EXE] [-v]
#
#   exact16   16 watertight pieces, volume kept (volume_rel_error < 1e-9)
#   more      more than 16 watertight pieces (separate shells cut apart)
#   fewer     fewer than 16 pieces, with the warning saying why
#   refused   the command refused the model; the reasons are tallied below
#   crashed   killed by a signal or out of time (120 s): a bug
#
# -v prints one line per model. The executable defaults to build/breakables.
set -uo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
exe="$repo/build/breakables"
verbose=0
for arg in "$@"; do
  case "$arg" in
  -v) verbose=1 ;;
  *) exe="$arg" ;;
  esac
done
if [[ ! -x "$exe" ]]; then
  echo "import_tally: no executable at $exe (build first, or pass its path)" >&2
  exit 2
fi
models="$(dpkg -L assimp-testmodels 2>/dev/null | grep -m1 '/models$' || true)"
models="${models:-/usr/share/assimp/models}"
if [[ ! -d "$models" ]]; then
  echo "import_tally: assimp-testmodels is not installed (scripts/setup.sh installs it)" >&2
  exit 2
fi

# The formats --mesh reads (BK_IMPORT_EXTENSIONS in include/breakables/authoring.h).
extensions="obj gltf glb fbx dae ply stl 3ds off 3mf blend x ac ase"
scratch="$(mktemp -d "${TMPDIR:-/tmp}/bk-tally.XXXXXX")"
trap 'rm -rf "$scratch"' EXIT
results="$scratch/results"
: >"$results"

find_args=()
for ext in $extensions; do
  find_args+=(-o -iname "*.$ext")
done
while IFS= read -r -d '' file; do
  ext="${file##*.}"
  ext="${ext,,}"
  status=0
  timeout 120 "$exe" fracture --mesh "$file" --pieces 16 --json >"$scratch/out" 2>"$scratch/err" || status=$?
  json="$(cat "$scratch/out")"
  reason=""
  if ((status == 0)); then
    made="$(sed -n 's/.*"pieces_made": \([0-9]*\).*/\1/p' <<<"$json")"
    watertight="$(sed -n 's/.*"watertight": \([a-z]*\).*/\1/p' <<<"$json")"
    volume="$(sed -n 's/.*"volume_rel_error": \([-0-9.e+]*\).*/\1/p' <<<"$json")"
    if [[ "$watertight" != true ]] || awk -v v="$volume" 'BEGIN { exit !(v > 1e-9) }'; then
      outcome=broken
    elif ((made == 16)); then
      outcome=exact16
    elif ((made > 16)); then
      outcome=more
    else
      outcome=fewer
      reason="$(sed -n 's/.*"warnings": \["\([^"]*\)".*/\1/p' <<<"$json" | sed 's/made [0-9]* of the 16 pieces asked for: //')"
    fi
  elif ((status == 1)); then
    outcome=refused
    # The reason without the path and the numbers, so alike refusals group.
    reason="$(grep '^breakables fracture: ' "$scratch/err" | tail -n 1 | sed "s|^breakables fracture: ||; s|$file: ||; s|$file||g" |
      sed -E 's/"[^"]*"/"..."/g; s/'"'"'[^'"'"']*'"'"'/'"'"'...'"'"'/g; s/-?[0-9]+(\.[0-9]+)?(e[-+]?[0-9]+)?/N/g' | cut -c1-110)"
  else
    outcome=crashed
    reason="exit status $status"
  fi
  printf '%s\t%s\t%s\t%s\n' "$ext" "$outcome" "$reason" "${file#"$models"/}" >>"$results"
  if ((verbose)); then printf '%-8s %-5s %s %s\n' "$outcome" "$ext" "${file#"$models"/}" "$reason"; fi
done < <(find "$models" -type f \( -false "${find_args[@]}" \) -print0 | sort -z)

total="$(wc -l <"$results")"
echo "import tally: $total models of $models in formats: $extensions"
echo
awk -F'\t' '
  { count[$1, $2]++; formats[$1]++; outcomes[$2]++ }
  END {
    n = split("exact16 more fewer refused broken crashed", order, " ")
    printf "%-7s", "format"
    for (i = 1; i <= n; ++i) printf " %8s", order[i]
    printf " %8s\n", "total"
    for (f in formats) {
      printf "%-7s", f
      for (i = 1; i <= n; ++i) printf " %8d", count[f, order[i]]
      printf " %8d\n", formats[f]
    }
    printf "~all   "
    for (i = 1; i <= n; ++i) printf " %8d", outcomes[order[i]]
    printf " %8d\n", NR
  }' "$results" | { read -r header; echo "$header"; sort | sed 's/^~all   /all    /'; }
echo
echo "refusals and shortfalls by reason:"
awk -F'\t' '$2 == "refused" || $2 == "fewer" || $2 == "crashed" { print $2 ": " $3 }' "$results" |
  sort | uniq -c | sort -rn
