#!/usr/bin/env bash
# The planes pattern against Manifold's WASM build (npm package manifold-3d)
# making the same cuts: a cube into 4096 pieces. Runs our fracture 3 times
# (median of its "ms", the tree's build time), then replays the last tree's
# cuts with Manifold's splitByPlane (tests/js/manifold_cuts.mjs: median of 3
# runs in one process, leaf count and leaf volumes checked against ours) and
# prints its JSON line and the ratio. The README's Benchmarks section quotes it.
#
#   scripts/manifold_compare.sh [BREAKABLES [PIECES]]   (default build-r/breakables 4096)
#
# Needs node and tests/js/node_modules (npm ci --prefix tests/js, which this
# runs when manifold-3d is missing). Ours runs on every core (its default,
# the same tree for any count), Manifold's WASM build on one; the load
# average is printed, since other jobs on the machine move both times.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin="${1:-$here/build-r/breakables}"
pieces="${2:-4096}"
js="$here/tests/js"
if [[ ! -x "$bin" ]]; then
  echo "manifold_compare: $bin is not an executable: build Release (scripts/run.sh builds build/breakables) or pass the binary" >&2
  exit 2
fi
if ! command -v node >/dev/null 2>&1; then
  echo "manifold_compare: node is not installed: run scripts/setup.sh" >&2
  exit 1
fi
if [[ ! -d "$js/node_modules/manifold-3d" ]]; then
  echo "manifold_compare: installing the npm packages of tests/js (npm ci)"
  npm ci --prefix "$js" --no-audit --no-fund
fi

tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
tree="$tmp/cube$pieces.mtree"
field() { grep -o "\"$1\": [^,}]*" <<<"$2" | head -n 1 | sed 's/.*: //'; }

echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg) ($(nproc) cores)"
ours=()
for run in 1 2 3; do
  out="$("$bin" fracture --mesh cube --pieces "$pieces" --out "$tree" --json)"
  ms="$(field ms "$out")"
  made="$(field pieces_made "$out")"
  [[ "$made" == "$pieces" ]] || { echo "manifold_compare: fracture made $made pieces, not $pieces" >&2; exit 1; }
  ours+=("$ms")
  echo "breakables fracture run $run: $ms ms"
done
median="$(printf '%s\n' "${ours[@]}" | sort -g | sed -n 2p)"

result="$(node "$js/manifold_cuts.mjs" "$tree" --ours-ms "$median")"
echo "$result"
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
manifold_ms="$(grep -o '"manifold_ms":[^,}]*' <<<"$result" | sed 's/.*://')"
ratio="$(grep -o '"ratio":[^,}]*' <<<"$result" | sed 's/.*://')"
version="$(grep -o '"manifold_version":"[^"]*"' <<<"$result" | sed 's/.*:"//; s/"//')"
check="$(grep -o '"volume_check":"[^"]*"' <<<"$result" | sed 's/.*:"//; s/"//')"
echo "planes, cube into $pieces pieces: breakables $median ms, manifold-3d $version (WASM) $manifold_ms ms:" \
  "ours ${ratio}x faster (volume check: $check)"
