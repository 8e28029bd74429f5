#!/usr/bin/env bash
# Regenerates the material textures in assets/textures/ with tools/make_textures.c
# (CMake target `make_textures`, not part of the default build).
#
# All textures are 256x256 PNGs that tile seamlessly in both directions and
# are fully deterministic (fixed noise seeds), so re-running this script
# reproduces the same files. For each material M in
#   stone brick concrete porcelain glass eggshell wood
# it writes
#   M_albedo.png           outer surface colour (RGB, sRGB),
#   M_normal.png           tangent-space normal map (RGB; OpenGL convention:
#                          +X right, +Y towards the top row of the image, +Z out
#                          of the surface; 128,128,255 is flat),
#   M_interior.png         colour of freshly broken / cut interior surfaces
#                          (RGB, sRGB): the inside of the material,
#   M_interior_normal.png  the broken surface's relief (RGBA: RGB a normal map
#                          as above, A ambient occlusion, 255 open),
# plus ground_albedo.png and ground_normal.png (stone paving slabs).
# tests/test_texture.c checks the interiors (sizes, seams, colour ranges,
# normals, occlusion).
#
# Usage: scripts/make_textures.sh   (BUILD_DIR overrides the build directory)
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo"

build="${BUILD_DIR:-build}"
out="$repo/assets/textures"

if [[ ! -f "$build/CMakeCache.txt" ]]; then
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release
fi
cmake --build "$build" --target make_textures -j
mkdir -p "$out"
"$build/make_textures" "$out"
