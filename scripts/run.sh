#!/usr/bin/env bash
# Release build, then runs the program with the given arguments, e.g.
#   scripts/run.sh fracture --mesh bunny --pieces 256
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo"

scripts/setup.sh >&2

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >&2
cmake --build build -j >&2
exec "$repo/build/breakables" "$@"
