#!/usr/bin/env bash
# ctest's test_gltf_blender: writes the glTF exports of tests/test_gltf.c
# (`test_gltf --export DIR`, one line of expected counts per file) and
# imports each into Blender (check_gltf.py). Skipped (exit 77) with a
# message when Blender or its numpy is missing (scripts/setup.sh installs them).
#
#   tests/blender/run_checks.sh TEST_GLTF_EXECUTABLE OUT_DIR
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
if [[ $# -ne 2 ]]; then
  echo "usage: $0 TEST_GLTF_EXECUTABLE OUT_DIR" >&2
  exit 2
fi
if ! command -v blender >/dev/null 2>&1; then
  echo "test_gltf_blender: skipped: blender is not installed (scripts/setup.sh installs Debian's blender)"
  exit 77
fi
if ! blender --background --factory-startup --python-exit-code 1 --python-expr 'import numpy' >/dev/null 2>&1; then
  echo "test_gltf_blender: skipped: Blender's glTF importer needs numpy (scripts/setup.sh installs python3-numpy)"
  exit 77
fi
out="$2"
rm -rf "$out"
mkdir -p "$out"
"$1" --export "$out" >"$out/exports.txt"
count=0
while read -r file args; do
  # Blender takes a few seconds to start: the files of every kind and level, not every copy.
  case "$(basename "$file")" in
  cube16_hierarchy.gltf | cube16_leaves.glb | cube16_all.glb | cube16_shipped.glb | two_materials.glb | voronoi48.glb) ;;
  *) continue ;;
  esac
  # --textures and --tree are the three.js check's; Blender's takes the rest.
  # shellcheck disable=SC2086 # the expected counts are separate arguments
  set -- $args
  kept=()
  while (($#)); do
    case "$1" in
    --textures | --tree | --materials) shift 2 ;;
    *)
      kept+=("$1" "$2")
      shift 2
      ;;
    esac
  done
  # Blender exits 0 even when a --python script fails: the script's output says.
  log="$(dirname "$file")/$(basename "$file").blender.log"
  blender --background --factory-startup --python-exit-code 1 --python "$here/check_gltf.py" -- "$file" \
    "${kept[@]}" >"$log" 2>&1 || {
    grep -E "check_gltf_blender|Error|Traceback" "$log" >&2 || tail -20 "$log" >&2
    exit 1
  }
  grep -E ": Blender [0-9]" "$log"
  count=$((count + 1))
done <"$out/exports.txt"
if ((count != 6)); then
  echo "test_gltf_blender: $count of the 6 exports were checked" >&2
  exit 1
fi
echo "test_gltf_blender: $count exports import into Blender as expected"
