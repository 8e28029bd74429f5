#!/usr/bin/env bash
# Release build, then runs the program with the given arguments, e.g.
#   scripts/run.sh fracture --mesh bunny --pieces 256
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo"

# Only what the game needs: no test models, fuzzer or npm (it starts with
# no network but the package mirror), and only the program is built.
scripts/setup.sh --game >&2

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >&2
cmake --build build -j "$(nproc)" --target breakables >&2
exec "$repo/build/breakables" "$@"
