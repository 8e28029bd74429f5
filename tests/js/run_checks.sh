#!/usr/bin/env bash
# ctest's test_gltf_js: writes the glTF exports of tests/test_gltf.c
# (`test_gltf --export DIR`, one line of expected counts per file) and checks
# each with Khronos's glTF validator and three.js (check_gltf.mjs).
#
#   tests/js/run_checks.sh TEST_GLTF_EXECUTABLE OUT_DIR
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
if [[ $# -ne 2 ]]; then
  echo "usage: $0 TEST_GLTF_EXECUTABLE OUT_DIR" >&2
  exit 2
fi
if ! command -v node >/dev/null 2>&1; then
  echo "test_gltf_js: node is not installed: run scripts/setup.sh" >&2
  exit 1
fi
for package in gltf-validator three; do
  if [[ ! -d "$here/node_modules/$package" ]]; then
    echo "test_gltf_js: $here/node_modules/$package is missing: run scripts/setup.sh (npm ci --prefix tests/js)" >&2
    exit 1
  fi
done
rm -rf "$2"
mkdir -p "$2"
"$1" --export "$2" >"$2/exports.txt"
count=0
while read -r file args; do
  # shellcheck disable=SC2086 # the expected counts are separate arguments
  node "$here/check_gltf.mjs" "$file" $args
  count=$((count + 1))
done <"$2/exports.txt"
if ((count == 0)); then
  echo "test_gltf_js: test_gltf wrote no exports" >&2
  exit 1
fi
echo "test_gltf_js: $count exports pass the validator and three.js"
