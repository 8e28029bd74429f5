#!/usr/bin/env bash
# Installs the Debian packages this project needs, if any is missing.
# Safe to run repeatedly: it does nothing when everything is present.
#   scripts/setup.sh          everything: the game, the tests, fuzzing, the checks
#   scripts/setup.sh --game   only what building and running the game needs
#                             (scripts/run.sh): no compilers for fuzzing, no
#                             test models, no npm, so no network beyond apt
#   scripts/setup.sh --web    only what the browser page needs (scripts/web.sh):
#                             emscripten, chromium, node, the npm packages of
#                             web/ and the GLU source of the WebAssembly build
set -euo pipefail

game_only=0
web_only=0
if [[ $# -gt 1 ]]; then
  echo "setup: one option at most (--game, --web or nothing)" >&2
  exit 2
elif [[ "${1:-}" == "--game" ]]; then
  game_only=1
elif [[ "${1:-}" == "--web" ]]; then
  web_only=1
elif [[ $# -gt 0 ]]; then
  echo "setup: unknown option '$1' (use --game, --web or nothing)" >&2
  exit 2
fi

PACKAGES=(
  build-essential
  cmake
  pkg-config
  clang-format
  # clang's libFuzzer for the fuzz harnesses (scripts/fuzz.sh); its runtime
  # libraries (libFuzzer, ASan, UBSan) come in a package of their own.
  clang
  libclang-rt-dev
  libglu1-mesa-dev
  python3-glad
  libbullet-dev
  libimgui-dev
  libglfw3-dev
  libcglm-dev
  libstb-dev
  # model import (glTF, FBX, PLY, STL, ...) through assimp's C API, and its
  # sample models (tests/test_import.c, scripts/import_tally.sh)
  libassimp-dev
  assimp-testmodels
  # the glTF export's optional vertex compression (EXT_meshopt_compression)
  libmeshoptimizer-dev
  # the runtime's state hash (XXH3, header only: nothing to link)
  libxxhash-dev
  # the destruction stream's compression (sim --serve, breakables serve)
  libzstd-dev
  # de_DE's locale source, compiled by test_obj to check OBJ numbers under a decimal comma
  locales
  xvfb
  xauth
  gnuplot-nox
  nodejs
  npm
  # the Blender import check of the glTF export (tests/blender; its glTF importer needs numpy)
  blender
  python3-numpy
)

# What only the tests, fuzzing, the checks and the tools need; --game leaves
# these out (the game builds from the committed OpenGL loader and needs no
# formatter, fuzzer, test models, plotting, virtual display or npm).
TEST_ONLY=(clang-format clang libclang-rt-dev python3-glad assimp-testmodels locales xvfb xauth gnuplot-nox
  nodejs npm blender python3-numpy)
if ((game_only)); then
  kept=()
  for pkg in "${PACKAGES[@]}"; do
    skip=0
    for t in "${TEST_ONLY[@]}"; do
      [[ "$pkg" == "$t" ]] && skip=1
    done
    ((skip)) || kept+=("$pkg")
  done
  PACKAGES=("${kept[@]}")
fi

# The browser page (scripts/web.sh): Debian's emscripten builds the libraries
# to WebAssembly (with cmake and make, and Debian's header-only stb and
# xxhash), node runs the page's tools, chromium runs the browser test
# (tests/web), whose screenshots need a font. Kept out of the plain set-up:
# emscripten and chromium are large, and the test suite does not need them.
WEB_PACKAGES=(cmake make libstb-dev libxxhash-dev emscripten nodejs npm chromium fonts-dejavu-core)
if ((web_only)); then
  PACKAGES=("${WEB_PACKAGES[@]}")
fi

is_installed() {
  local pkg="$1" status
  status="$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)"
  if [[ "$status" == "install ok installed" ]]; then
    return 0
  fi
  # Some nodejs builds bundle npm (and conflict with Debian's npm package);
  # a working npm command counts as present.
  if [[ "$pkg" == "npm" ]] && command -v npm >/dev/null 2>&1; then
    return 0
  fi
  return 1
}

# The npm packages of the glTF checks and the Manifold comparison (tests/js:
# gltf-validator, three, manifold-3d, pinned by tests/js/package-lock.json),
# installed into tests/js/node_modules
# (git-ignored) when missing: the build and the tests never download.
install_js_packages() {
  ((game_only)) && return 0 # the game needs none
  if ((web_only)); then
    install_web_packages
    return 0
  fi
  local js
  js="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/tests/js"
  if [[ -d "$js/node_modules/gltf-validator" && -d "$js/node_modules/three" &&
    -d "$js/node_modules/manifold-3d" ]]; then
    return 0
  fi
  echo "setup: installing the npm packages of tests/js (npm ci)"
  npm ci --prefix "$js" --no-audit --no-fund
}

# The npm packages of the page and its test (web: three, Rapier's
# @dimforge/rapier3d-compat, puppeteer-core, pinned by web/package-lock.json)
# into web/node_modules (git-ignored), again when the lock file is newer than
# what npm installed; puppeteer-core downloads no browser (the test runs
# Debian's chromium). Then the GLU source the WebAssembly build compiles
# (scripts/web_glu.sh, into web/.deps; nothing when it is there).
install_web_packages() {
  local repo web
  repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
  web="$repo/web"
  if [[ ! -d "$web/node_modules/three" || ! -d "$web/node_modules/@dimforge/rapier3d-compat" ||
    ! -d "$web/node_modules/puppeteer-core" || "$web/package-lock.json" -nt "$web/node_modules/.package-lock.json" ]]; then
    echo "setup: installing the npm packages of web (npm ci)"
    PUPPETEER_SKIP_DOWNLOAD=1 npm ci --prefix "$web" --no-audit --no-fund
  fi
  if [[ -f "$repo/scripts/web_glu.sh" ]]; then
    bash "$repo/scripts/web_glu.sh"
  fi
}

missing=()
for pkg in "${PACKAGES[@]}"; do
  if ! is_installed "$pkg"; then
    missing+=("$pkg")
  fi
done

if ((${#missing[@]} == 0)); then
  echo "setup: all ${#PACKAGES[@]} required packages are present"
  install_js_packages
  exit 0
fi

echo "setup: installing missing packages: ${missing[*]}"

SUDO=()
if [[ "$(id -u)" -ne 0 ]]; then
  if command -v sudo >/dev/null 2>&1; then
    SUDO=(sudo)
  else
    echo "setup: not root and sudo is unavailable; install these packages: ${missing[*]}" >&2
    exit 1
  fi
fi

export DEBIAN_FRONTEND=noninteractive
"${SUDO[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update
"${SUDO[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${missing[@]}"
install_js_packages
echo "setup: done"
