#!/usr/bin/env bash
# Builds the browser page and serves it on 127.0.0.1:
#   1. scripts/setup.sh --web: emscripten, chromium, the npm packages of web/
#      and the GLU source (installed when missing; nothing otherwise);
#   2. the authoring and runtime libraries to WebAssembly with Debian's
#      emscripten (web/CMakeLists.txt, into build-web/);
#   3. web/dist/: the page, the module, the bunny and the files of three and
#      Rapier it imports (web/tools/assemble.mjs);
#   4. serves web/dist (web/tools/serve.mjs) until interrupted.
# usage: scripts/web.sh [--port P] [--build-only] [--test [-- TEST OPTIONS]]
#   --port P      serve on 127.0.0.1:P (default 8080)
#   --build-only  stop after building web/dist
#   --test        run the browser test (tests/web/browser_test.mjs) on the
#                 build instead of serving; what follows -- goes to the test
#                 (e.g. -- --screenshot page.png --json numbers.json)
set -euo pipefail

usage() {
  sed -n '/^# usage:/,/^set -e/{/^set/d;s/^# \{0,1\}//;p}' "${BASH_SOURCE[0]}" >&2
  exit 2
}

port=8080
build_only=0
run_test=0
test_args=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --port)
      [[ $# -ge 2 && "$2" =~ ^[0-9]+$ && "$2" -ge 1 && "$2" -le 65535 ]] || {
        echo "web: --port wants a number 1..65535" >&2
        exit 2
      }
      port="$2"
      shift 2
      ;;
    --build-only) build_only=1 && shift ;;
    --test) run_test=1 && shift ;;
    --)
      shift
      test_args=("$@")
      break
      ;;
    -h | --help) usage ;;
    *)
      echo "web: unknown option '$1'" >&2
      usage
      ;;
  esac
done
if ((${#test_args[@]} > 0 && !run_test)); then
  echo "web: options after -- are the browser test's: give --test" >&2
  exit 2
fi

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo"

scripts/setup.sh --web

# Debian's emcc runs its JavaScript tools with the node on the PATH, which
# finds Debian's node modules (acorn) only through NODE_PATH when that node is
# not Debian's own.
export NODE_PATH="/usr/share/nodejs${NODE_PATH:+:$NODE_PATH}"
# emscripten keeps its system libraries (Debian ships them built) in a cache
# under /usr/share/emscripten, which it locks for writing; a user who may not
# write there gets a copy of their own.
packaged_cache=/usr/share/emscripten/cache
if [[ -z "${EM_CACHE:-}" && -d "$packaged_cache" && ! -w "$packaged_cache" ]]; then
  export EM_CACHE="${XDG_CACHE_HOME:-$HOME/.cache}/emscripten"
  if [[ ! -d "$EM_CACHE" ]]; then
    mkdir -p "$(dirname "$EM_CACHE")"
    cp -r "$packaged_cache" "$EM_CACHE"
  fi
fi

if [[ ! -f build-web/CMakeCache.txt ]]; then
  emcmake cmake -S web -B build-web -DCMAKE_BUILD_TYPE=Release
fi
cmake --build build-web -j"$(nproc)"
node web/tools/assemble.mjs

if ((run_test)); then
  # The module under node first (its trees against tests/tree_hashes.txt),
  # then the page in chromium.
  node --no-experimental-fetch web/tests/module_check.mjs web/dist
  exec node tests/web/browser_test.mjs "${test_args[@]}"
fi
if ((build_only)); then
  exit 0
fi
echo "web: open http://127.0.0.1:$port/ (Ctrl-C stops)"
exec node web/tools/serve.mjs --port "$port"
