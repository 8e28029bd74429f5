#!/usr/bin/env bash
# Installs the Debian packages this project needs, if any is missing.
# Safe to run repeatedly: it does nothing when everything is present.
set -euo pipefail

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
  # de_DE's locale source, compiled by test_obj to check OBJ numbers under a decimal comma
  locales
  xvfb
  xauth
  gnuplot-nox
  nodejs
  npm
)

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
  local js
  js="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/tests/js"
  if [[ -d "$js/node_modules/gltf-validator" && -d "$js/node_modules/three" &&
    -d "$js/node_modules/manifold-3d" ]]; then
    return 0
  fi
  echo "setup: installing the npm packages of tests/js (npm ci)"
  npm ci --prefix "$js" --no-audit --no-fund
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
