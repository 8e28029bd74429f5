#!/usr/bin/env bash
# Checks what `cmake --install` gives a user, from a copy of the source tree in
# a temporary directory (never the repository's own build directories):
#   install   Release build with the demo, installed with --prefix;
#   layout    headers (public ones only), static libraries, CMake package,
#             pkg-config files, the executable and its data;
#   symbols   the runtime and authoring libraries need nothing from Bullet, GL,
#             GLFW, ImGui or the C++ runtime (nm -u); runtime nothing from bullet;
#   shared    the shared libraries: soname, links, run path, only bk_ names
#             exported and every public function among them;
#   pkg-config  breakables-runtime names no Bullet, breakables-bullet does;
#             programs linked with plain `pkg-config --libs` (the shared
#             libraries) run with no LD_LIBRARY_PATH;
#   shared-use  the CMake package's shared targets link programs that run;
#             Python's ctypes loads libbreakables-runtime.so and calls it;
#   examples  each of examples/ built against the prefix with find_package (and
#             own_physics with plain pkg-config flags), run; own_physics gives
#             the same output every time and its binary has no Bullet in it;
#   subproject  add_subdirectory(breakables) with BK_BUILD_DEMO=OFF;
#   headless  a build without the demo (BK_BUILD_DEMO=OFF): none of the
#             demo's dependencies looked up, its tests pass; its installed
#             breakables runs fracture and sim and loads no GLFW, GL or ImGui;
#   no-bullet an install without Bullet (BK_BUILD_BULLET=OFF) builds the
#             runtime examples and refuses COMPONENTS bullet with a message;
#   relocated the installed executable, with the source and build trees moved
#             away: a headless fracture and a scripted game under xvfb-run.
# Prints one line per check passed; the first failure names its check, shows
# the end of its log and stops the script (exit 1). The temporary directory is
# removed on success and kept on failure (its path is printed).
#
#   scripts/check_install.sh
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo"

scripts/setup.sh >/dev/null

tmp="$(mktemp -d "${TMPDIR:-/tmp}/bk-install.XXXXXX")"
prefix="$tmp/prefix"
logs="$tmp/logs"
mkdir -p "$logs"
start_seconds=$SECONDS
finished=0
on_exit() {
  if ((finished)); then
    rm -rf "$tmp"
  else
    echo "check_install: the temporary directory is kept for inspection: $tmp" >&2
  fi
}
trap on_exit EXIT

ok() { echo "check_install: ok: $*"; }
fail() {
  echo "check_install: FAILED: $1: $2" >&2
  exit 1
}
# run CHECK LOG COMMAND...: runs the command with its output in $logs/LOG; on
# failure shows the log's end and fails CHECK.
run() {
  local check="$1" log="$logs/$2"
  shift 2
  if ! "$@" >"$log" 2>&1; then
    tail -n 30 "$log" >&2
    fail "$check" "'$*' failed (log: $log)"
  fi
}
# Undefined symbols of a static library, one per line.
undefined_symbols() { nm -u "$1" | awk '$1 == "U" { print $2 }' | sort -u; }
defined_symbols() { nm -g --defined-only "$1" | awk 'NF == 3 { print $3 }' | sort -u; }

# Bullet's C++ API (btVector3, btAlignedAllocInternal, mangled _ZN..bt..), GL,
# GLFW, Dear ImGui and the C++ runtime. GLU (glu*) is allowed in authoring: it
# triangulates the cut caps with GLU's tessellator.
bullet_re='bt[A-Z]|Bullet'
declare -A forbidden=([Bullet]="$bullet_re" [GL]='^gl[A-Z]' [GLFW]='^glfw' [ImGui]='ImGui|^ig[A-Z]'
  [C++ runtime]='^_Z|^__cxa_|^__gxx_')

# ---------------------------------------------------------------- a. install
# The working tree as it is: in a git checkout its tracked and new files (not
# the ignored ones, such as build*/), else everything but build*/ and .git.
mkdir "$tmp/src"
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  git ls-files -z --cached --others --exclude-standard | while IFS= read -r -d '' file; do
    if [[ -f "$file" ]]; then printf '%s\0' "$file"; fi
  done | xargs -0 cp --parents -t "$tmp/src"
else
  find . -mindepth 1 -maxdepth 1 ! -name 'build*' ! -name .git -exec cp -r -t "$tmp/src" {} +
fi
# The test's npm packages are installed by scripts/setup.sh, like the system's:
# the copy uses the same ones (a link, nothing downloaded).
if [[ -d tests/js/node_modules ]]; then ln -s "$PWD/tests/js/node_modules" "$tmp/src/tests/js/node_modules"; fi
[[ -f "$tmp/src/CMakeLists.txt" && -d "$tmp/src/examples" ]] || fail install "the source copy is incomplete"
ok "source copied ($(find "$tmp/src" -type f | wc -l) files)"

run install install-configure.log cmake -S "$tmp/src" -B "$tmp/build" -DCMAKE_BUILD_TYPE=Release -DBK_BUILD_DEMO=ON \
  -DBK_BUILD_TESTS=OFF
build_start=$SECONDS
run install install-build.log cmake --build "$tmp/build" -j2
# --prefix, not the configured CMAKE_INSTALL_PREFIX: the package must follow it.
run install install-install.log cmake --install "$tmp/build" --prefix "$prefix"
ok "release build with the demo in $((SECONDS - build_start)) s, installed into $prefix"

# ---------------------------------------------------------------- b. layout
public_headers=(types.h base.h authoring.h runtime.h bullet.h)
for header in "${public_headers[@]}"; do
  [[ -s "$prefix/include/breakables/$header" ]] || fail layout "include/breakables/$header is missing"
done
extra_headers="$(find "$prefix/include" -type f | grep -vE '/include/breakables/(types|base|authoring|runtime|bullet)\.h$' || true)"
[[ -z "$extra_headers" ]] || fail layout "headers that are not public were installed: $extra_headers"
# Each public header stands alone in C11 and includes only public headers.
for header in "${public_headers[@]}"; do
  echo "#include <breakables/$header>" >"$tmp/header_check.c"
  run layout "header_$header.log" cc -std=c11 -Wall -Wextra -Werror -pedantic -fsyntax-only -I"$prefix/include" \
    "$tmp/header_check.c"
  if grep -E '^#include "' "$prefix/include/breakables/$header" | grep -vqE '"(types|base|authoring|runtime)\.h"'; then
    fail layout "$header includes a header that is not installed"
  fi
done
for file in lib/libbreakables-authoring.a lib/libbreakables-runtime.a lib/libbreakables-bullet.a \
  lib/libbreakables-authoring.so lib/libbreakables-runtime.so lib/libbreakables-bullet.so \
  lib/cmake/breakables/breakables-config.cmake lib/cmake/breakables/breakables-config-version.cmake \
  lib/pkgconfig/breakables-authoring.pc lib/pkgconfig/breakables-runtime.pc lib/pkgconfig/breakables-bullet.pc \
  bin/breakables share/breakables/assets/meshes/bunny.obj share/breakables/shaders/mesh.vert \
  share/doc/breakables/embedding.md share/doc/breakables/gltf.md share/doc/breakables/patterns.md; do
  [[ -s "$prefix/$file" ]] || fail layout "$file is missing or empty"
done
[[ -x "$prefix/bin/breakables" ]] || fail layout "bin/breakables is not executable"
for dir in share/breakables/assets/textures share/breakables/shaders; do
  [[ -n "$(ls -A "$prefix/$dir")" ]] || fail layout "$dir is empty"
done
# The documents the headers name are installed beside them.
for doc in $(grep -ohE '[a-z_]+\.md' "$prefix"/include/breakables/*.h | sort -u); do
  [[ -s "$prefix/share/doc/breakables/$doc" ]] || fail layout "a header names $doc, which is not installed"
done
# Nothing installed may point back into the source or build trees.
if grep -rlF -e "$tmp/src" -e "$tmp/build" "$prefix/lib/cmake" "$prefix/lib/pkgconfig"; then
  fail layout "the CMake package or a .pc file names the source or build directory"
fi
ok "layout: 4 public headers (each compiles alone), 3 static and 3 shared libraries, CMake package, 3 .pc files, bin/breakables, share/breakables/{assets,shaders}, share/doc/breakables (the documents the headers name)"

# ---------------------------------------------------------------- c. symbols
authoring_lib="$prefix/lib/libbreakables-authoring.a"
runtime_lib="$prefix/lib/libbreakables-runtime.a"
bullet_lib="$prefix/lib/libbreakables-bullet.a"
undefined_symbols "$authoring_lib" >"$tmp/authoring.undefined"
undefined_symbols "$runtime_lib" >"$tmp/runtime.undefined"
undefined_symbols "$bullet_lib" >"$tmp/bullet.undefined"
# The patterns must match what they are meant to: bullet's library uses Bullet.
grep -qE "$bullet_re" "$tmp/bullet.undefined" || fail symbols "no Bullet symbol found in libbreakables-bullet.a: the check itself is broken"
grep -qE '^glu' "$tmp/authoring.undefined" || fail symbols "no GLU symbol found in libbreakables-authoring.a: the check itself is broken"
for lib in authoring runtime; do
  for name in "${!forbidden[@]}"; do
    found="$(grep -E "${forbidden[$name]}" "$tmp/$lib.undefined" | head -n 5 | tr '\n' ' ' || true)"
    [[ -z "$found" ]] || fail symbols "libbreakables-$lib.a needs $name symbols: $found"
  done
done
# Nothing the bullet library defines; authoring needs nothing from runtime either.
defined_symbols "$bullet_lib" >"$tmp/bullet.defined"
defined_symbols "$runtime_lib" >"$tmp/runtime.defined"
found="$(comm -12 "$tmp/runtime.undefined" "$tmp/bullet.defined" | head -n 5 | tr '\n' ' ')"
[[ -z "$found" ]] || fail symbols "libbreakables-runtime.a needs symbols of libbreakables-bullet.a: $found"
found="$(sort -u "$tmp/bullet.defined" "$tmp/runtime.defined" | comm -12 "$tmp/authoring.undefined" - | head -n 5 | tr '\n' ' ')"
[[ -z "$found" ]] || fail symbols "libbreakables-authoring.a needs symbols of runtime or bullet: $found"
ok "symbols: runtime ($(wc -l <"$tmp/runtime.undefined") undefined) and authoring ($(wc -l <"$tmp/authoring.undefined")) need no Bullet, GL, GLFW, ImGui or C++ runtime; runtime nothing of bullet"

# ---------------------------------------------------------------- c2. shared
# The soname follows the package's compatibility (SameMinorVersion): .so.0.1
# for 0.1.x, .so.<major> from 1.0. The links are .so -> .so.<soversion> ->
# .so.<version>; the run path $ORIGIN finds the sibling libraries wherever the
# prefix is. Only bk_ names are exported (the version script hides the C++ of
# Bullet and libstdc++ that the bullet library's objects define), and every
# function a public header declares is among them.
version="$(sed -n 's/^Version: //p' "$prefix/lib/pkgconfig/breakables-runtime.pc")"
IFS=. read -r major minor _ <<<"$version"
if ((major == 0)); then soversion="$major.$minor"; else soversion="$major"; fi
# Functions declared in a public header (not the static inline math).
public_functions() { cat "$@" | grep -vE '^\s*(static|typedef|//|#|\*)' | grep -oE '^[A-Za-z_][A-Za-z0-9_ *]*[ *]bk_[a-z0-9_]+\(' |
  grep -oE 'bk_[a-z0-9_]+\($' | tr -d '(' | sort -u; }
declare -A public_headers_of=([authoring]="types.h base.h authoring.h" [runtime]="runtime.h" [bullet]="bullet.h")
grep -qE '^_Z' "$tmp/bullet.defined" || fail shared "libbreakables-bullet.a defines no C++ symbol: the export check itself is broken"
for lib in authoring runtime bullet; do
  so="$prefix/lib/libbreakables-$lib.so"
  [[ "$(readlink "$so")" == "libbreakables-$lib.so.$soversion" ]] ||
    fail shared "libbreakables-$lib.so links to '$(readlink "$so")', not libbreakables-$lib.so.$soversion"
  [[ "$(readlink "$so.$soversion")" == "libbreakables-$lib.so.$version" && -f "$so.$version" ]] ||
    fail shared "libbreakables-$lib.so.$soversion links to '$(readlink "$so.$soversion")', not libbreakables-$lib.so.$version"
  dynamic="$(readelf -d "$so.$version")"
  soname="$(sed -n 's/.*Library soname: \[\(.*\)\]$/\1/p' <<<"$dynamic")"
  [[ "$soname" == "libbreakables-$lib.so.$soversion" ]] || fail shared "libbreakables-$lib.so's soname is '$soname', not libbreakables-$lib.so.$soversion"
  runpath="$(sed -n 's/.*Library runpath: \[\(.*\)\]$/\1/p' <<<"$dynamic")"
  [[ "$runpath" == '$ORIGIN' ]] || fail shared "libbreakables-$lib.so's run path is '$runpath', not \$ORIGIN"
  nm -D --defined-only "$so" | awk 'NF == 3 { print $3 }' | sort -u >"$tmp/$lib.exported"
  found="$(grep -v '^bk_' "$tmp/$lib.exported" | head -n 5 | tr '\n' ' ' || true)"
  [[ -z "$found" ]] || fail shared "libbreakables-$lib.so exports names that are not bk_: $found"
  # shellcheck disable=SC2086 # the header list is meant to split
  (cd "$prefix/include/breakables" && public_functions ${public_headers_of[$lib]}) >"$tmp/$lib.public"
  (($(wc -l <"$tmp/$lib.public") >= 3)) || fail shared "found no public function of $lib: the export check itself is broken"
  found="$(comm -23 "$tmp/$lib.public" "$tmp/$lib.exported" | head -n 5 | tr '\n' ' ')"
  [[ -z "$found" ]] || fail shared "libbreakables-$lib.so does not export public functions: $found"
done
ok "shared: libbreakables-{authoring,runtime,bullet}.so.$version, soname .so.$soversion, run path \$ORIGIN; they export only bk_ names ($(wc -l <"$tmp/authoring.exported"), $(wc -l <"$tmp/runtime.exported"), $(wc -l <"$tmp/bullet.exported")), every public function among them"

# ---------------------------------------------------------------- d. pkg-config
export PKG_CONFIG_PATH="$prefix/lib/pkgconfig"
for module in breakables-authoring breakables-runtime breakables-bullet; do
  pkg-config --exists --print-errors "$module" 2>"$logs/pkg-config.log" || fail pkg-config "$module: $(cat "$logs/pkg-config.log")"
  libdir="$(pkg-config --variable=libdir "$module")"
  [[ "$(cd "$libdir" && pwd -P)" == "$(cd "$prefix/lib" && pwd -P)" ]] || fail pkg-config "$module: libdir $libdir is not $prefix/lib"
done
runtime_libs="$(pkg-config --libs breakables-runtime)"
runtime_static_libs="$(pkg-config --static --libs breakables-runtime)"
bullet_static_libs="$(pkg-config --static --libs breakables-bullet)"
echo "check_install: pkg-config --libs breakables-runtime: $runtime_libs"
echo "check_install: pkg-config --static --libs breakables-runtime: $runtime_static_libs"
echo "check_install: pkg-config --static --libs breakables-bullet: $bullet_static_libs"
if grep -qiE 'bullet|LinearMath' <<<"$runtime_libs $runtime_static_libs"; then
  fail pkg-config "breakables-runtime names Bullet"
fi
for lib in -lbreakables-bullet -lbreakables-runtime -lbreakables-authoring -lBulletDynamics -lBulletCollision -lLinearMath; do
  grep -qwe "$lib" <<<"$bullet_static_libs" || fail pkg-config "pkg-config --static --libs breakables-bullet does not name $lib"
done
ok "pkg-config: breakables-runtime names no Bullet, breakables-bullet names Bullet's libraries"

# ---------------------------------------------------------------- e. examples
mapfile -t examples < <(cd "$tmp/src/examples" && find . -mindepth 2 -maxdepth 2 -name CMakeLists.txt -printf '%h\n' | sed 's|^\./||' | sort)
((${#examples[@]} >= 3)) || fail examples "expected at least 3 examples in examples/, found ${#examples[@]}"
for example in "${examples[@]}"; do
  build="$tmp/examples/$example"
  run examples "$example-configure.log" cmake -S "$tmp/src/examples/$example" -B "$build" -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$prefix"
  found_dir="$(sed -n 's/^breakables_DIR:PATH=//p' "$build/CMakeCache.txt")"
  [[ "$found_dir" == "$prefix/lib/cmake/breakables" ]] || fail examples "$example found breakables in '$found_dir', not in the prefix"
  run examples "$example-build.log" cmake --build "$build"
  mkdir -p "$tmp/run/$example"
  (cd "$tmp/run/$example" && "$build/$example" >"$logs/$example.out" 2>&1) ||
    { cat "$logs/$example.out" >&2; fail examples "$example failed"; }
  ok "example $example: built with find_package, ran ($(tail -n 1 "$logs/$example.out"))"
done
[[ -x "$tmp/examples/own_physics/own_physics" ]] || fail examples "there is no own_physics example"

# bake_and_load also takes an OBJ: the installed bunny.
(cd "$tmp/run/bake_and_load" && "$tmp/examples/bake_and_load/bake_and_load" "$prefix/share/breakables/assets/meshes/bunny.obj" \
  bunny.mtree >"$logs/bake_and_load_bunny.out" 2>&1) || { cat "$logs/bake_and_load_bunny.out" >&2; fail examples "bake_and_load bunny.obj failed"; }
[[ -s "$tmp/run/bake_and_load/bunny.mtree" ]] || fail examples "bake_and_load wrote no bunny.mtree"
ok "example bake_and_load with an OBJ ($(tail -n 1 "$logs/bake_and_load_bunny.out"))"

# own_physics and headless_wall as a project without CMake would build them,
# with plain `pkg-config --cflags --libs` (no --static): the linker takes the
# shared libraries, and the .pc files' run path finds them, so the programs
# run with no LD_LIBRARY_PATH.
# shellcheck disable=SC2046 # pkg-config's flags are meant to split
run examples own_physics_pkg-config.log cc -std=c11 -O2 -Wall -Wextra -Werror "$tmp/src/examples/own_physics/main.c" \
  -o "$tmp/own_physics_pc" $(pkg-config --cflags --libs breakables-runtime)
# shellcheck disable=SC2046
run examples headless_wall_pkg-config.log cc -std=c11 -O2 -Wall -Wextra -Werror "$tmp/src/examples/headless_wall/main.c" \
  -o "$tmp/headless_wall_pc" $(pkg-config --cflags --libs breakables-bullet)
"$tmp/examples/own_physics/own_physics" >"$logs/own_physics.2.out"
env -u LD_LIBRARY_PATH "$tmp/own_physics_pc" >"$logs/own_physics_pc.out" 2>&1 ||
  { cat "$logs/own_physics_pc.out" >&2; fail examples "own_physics linked with plain pkg-config --libs does not run"; }
(cd "$tmp/run/headless_wall" && env -u LD_LIBRARY_PATH "$tmp/headless_wall_pc" >"$logs/headless_wall_pc.out" 2>&1) ||
  { cat "$logs/headless_wall_pc.out" >&2; fail examples "headless_wall linked with plain pkg-config --libs does not run"; }
diff -u "$logs/own_physics.out" "$logs/own_physics.2.out" >&2 || fail examples "own_physics printed something else on its second run"
diff -u "$logs/own_physics.out" "$logs/own_physics_pc.out" >&2 || fail examples "own_physics built with pkg-config printed something else"
diff -u "$logs/headless_wall.out" "$logs/headless_wall_pc.out" >&2 || fail examples "headless_wall built with pkg-config printed something else"
for binary in own_physics_pc:runtime headless_wall_pc:bullet; do
  needed="$(readelf -d "$tmp/${binary%%:*}" | sed -n 's/.*(NEEDED).*\[\(.*\)\]$/\1/p' | tr '\n' ' ')"
  grep -qw "libbreakables-${binary#*:}\.so\.$soversion" <<<"$needed" ||
    fail examples "${binary%%:*} (plain pkg-config --libs) does not load libbreakables-${binary#*:}.so.$soversion: $needed"
done
ok "examples own_physics and headless_wall: linked with plain pkg-config --libs (the shared libraries), run without LD_LIBRARY_PATH, print the same"
for binary in "$tmp/examples/own_physics/own_physics" "$tmp/own_physics_pc"; do
  found="$(nm "$binary" | grep -E "$bullet_re" | head -n 3 | tr '\n' ' ' || true)"
  [[ -z "$found" ]] || fail examples "$binary has Bullet symbols: $found"
  # ldd's output is captured first: grep -q stops reading at its first match,
  # and under pipefail the pipeline would then fail on ldd's broken pipe.
  libs="$(ldd "$binary")"
  if grep -qiE 'bullet|LinearMath' <<<"$libs"; then fail examples "$binary loads Bullet: $(grep -iE 'bullet|LinearMath' <<<"$libs")"; fi
done
# ... while the Bullet example does load Bullet (the check can see it).
libs="$(ldd "$tmp/examples/headless_wall/headless_wall")"
grep -q libBulletDynamics <<<"$libs" || fail examples "headless_wall does not load Bullet: the check itself is broken"
ok "example own_physics: no Bullet symbol (nm) and no Bullet library (ldd) in its binaries"

# ---------------------------------------------------------------- shared-use
# The CMake package's shared targets: own_physics on breakables::runtime_shared
# and headless_wall on breakables::bullet_shared print what the static builds
# print, load the prefix's shared libraries, and hold no bk_ function themselves.
shared_use="$tmp/shared-use"
mkdir -p "$shared_use"
cp "$tmp/src/examples/own_physics/main.c" "$shared_use/own_physics.c"
cp "$tmp/src/examples/headless_wall/main.c" "$shared_use/headless_wall.c"
cat >"$shared_use/CMakeLists.txt" <<CMAKE
cmake_minimum_required(VERSION 3.20)
project(uses_shared LANGUAGES C)
find_package(breakables $version REQUIRED COMPONENTS bullet)
add_executable(own_physics own_physics.c)
target_link_libraries(own_physics PRIVATE breakables::runtime_shared)
add_executable(headless_wall headless_wall.c)
target_link_libraries(headless_wall PRIVATE breakables::bullet_shared)
CMAKE
run shared-use shared-use-configure.log cmake -S "$shared_use" -B "$shared_use/build" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix"
run shared-use shared-use-build.log cmake --build "$shared_use/build" -j2
for example in own_physics headless_wall; do
  binary="$shared_use/build/$example"
  (cd "$tmp/run/$example" && env -u LD_LIBRARY_PATH "$binary" >"$logs/$example-shared.out" 2>&1) ||
    { cat "$logs/$example-shared.out" >&2; fail shared-use "$example on the shared target does not run"; }
  diff -u "$logs/$example.out" "$logs/$example-shared.out" >&2 || fail shared-use "$example on the shared target printed something else"
  found="$(nm --defined-only "$binary" | awk '$3 ~ /^bk_/ { print $3 }' | head -n 3 | tr '\n' ' ')"
  [[ -z "$found" ]] || fail shared-use "$example on the shared target has the library inside: $found"
  libs="$(ldd "$binary")"
  grep -q "libbreakables-runtime.so.$soversion => $prefix/lib/" <<<"$libs" ||
    fail shared-use "$example on the shared target does not load the prefix's libbreakables-runtime.so: $libs"
done
ok "shared-use: own_physics on breakables::runtime_shared and headless_wall on breakables::bullet_shared run and print what the static builds print"

# Another language: Python's ctypes loads libbreakables-runtime.so (its run
# path brings in authoring), reads the version and the runtime's defaults, and
# gets a one-line error from bk_runtime_create for the missing callback.
cat >"$tmp/load.py" <<'PYTHON'
import ctypes
import sys

class Version(ctypes.Structure):
    _fields_ = [("major", ctypes.c_int), ("minor", ctypes.c_int), ("revision", ctypes.c_int)]

class RuntimeDef(ctypes.Structure):
    # The leading fields of bk_runtime_def, then room for the rest: returned
    # by value through a hidden pointer, as any struct of this size.
    _fields_ = [("impact_speed", ctypes.c_double), ("impulse_threshold", ctypes.c_double),
                ("damage_min_distance", ctypes.c_double), ("rest", ctypes.c_char * 4096)]

lib = ctypes.CDLL(sys.argv[1])
lib.bk_get_version.restype = Version
version = lib.bk_get_version()
lib.bk_default_runtime_def.restype = RuntimeDef
runtime_def = lib.bk_default_runtime_def()
lib.bk_runtime_create.restype = ctypes.c_void_p
error = ctypes.create_string_buffer(4096)
runtime = lib.bk_runtime_create(ctypes.byref(runtime_def), error)
print(f"version {version.major}.{version.minor}.{version.revision}")
print(f"impact_speed {runtime_def.impact_speed:g} damage_min_distance {runtime_def.damage_min_distance:g}")
print(f"create {'NULL' if runtime is None else 'made'}: {error.value.decode()}")
PYTHON
run python python.log env -u LD_LIBRARY_PATH python3 "$tmp/load.py" "$prefix/lib/libbreakables-runtime.so"
grep -qx "version $version" "$logs/python.log" || fail python "bk_get_version through ctypes is not $version: $(cat "$logs/python.log")"
grep -qx 'impact_speed 1 damage_min_distance 0.05' "$logs/python.log" ||
  fail python "bk_default_runtime_def through ctypes gave other defaults: $(cat "$logs/python.log")"
grep -qE '^create NULL: .*body_state' "$logs/python.log" ||
  fail python "bk_runtime_create without body_state did not fail naming it: $(cat "$logs/python.log")"
ok "python: ctypes loads libbreakables-runtime.so and calls it ($(paste -sd ';' "$logs/python.log"))"

# ---------------------------------------------------------------- f. subproject
sub="$tmp/subproject"
mkdir -p "$sub"
cp "$tmp/src/examples/own_physics/main.c" "$sub/main.c"
cat >"$sub/CMakeLists.txt" <<EOF
cmake_minimum_required(VERSION 3.20)
project(uses_breakables LANGUAGES C)
set(BK_BUILD_DEMO OFF)
add_subdirectory("$tmp/src" breakables)
add_executable(game main.c)
target_link_libraries(game PRIVATE breakables::runtime)
EOF
run subproject subproject-configure.log cmake -S "$sub" -B "$sub/build" -DCMAKE_BUILD_TYPE=Release
run subproject subproject-build.log cmake --build "$sub/build" -j2
"$sub/build/game" >"$logs/subproject.out" 2>&1 || { cat "$logs/subproject.out" >&2; fail subproject "the game built with add_subdirectory failed"; }
diff -u "$logs/own_physics.out" "$logs/subproject.out" >&2 || fail subproject "own_physics built with add_subdirectory printed something else"
for option in BK_BUILD_TESTS BK_INSTALL; do
  grep -qx "$option:BOOL=OFF" "$sub/build/CMakeCache.txt" || fail subproject "$option is not OFF in a sub-project"
done
if [[ -n "$(find "$sub/build/breakables" -type f \( -name 'libglad.a' -o -name 'libapp_ui.a' -o -name 'libapp_core.a' -o -name 'breakables' -o -name 'test_*' \))" ]]; then
  fail subproject "the demo, the command line or the tests were built as a sub-project"
fi
ok "subproject: add_subdirectory with BK_BUILD_DEMO=OFF builds and links breakables::runtime (no demo, no command line, no tests)"

# ---------------------------------------------------------------- g. headless
headless="$tmp/build-headless"
run headless headless-configure.log cmake -S "$tmp/src" -B "$headless" -DCMAKE_BUILD_TYPE=Release -DBK_BUILD_DEMO=OFF -DBK_BUILD_TESTS=ON
# Cache entries of the demo's lookups (pkg_check_modules, find_package(OpenGL)),
# by name: GLU's own entries may name libOpenGL, which authoring links.
demo_entries() { grep -vE '^(//|#)' "$1" | cut -d: -f1 | grep -E 'GLFW|IMGUI|CGLM|OPENGL|OpenGL' | head -n 5 || true; }
[[ -n "$(demo_entries "$tmp/build/CMakeCache.txt")" ]] || fail headless "no demo entry in the demo build's cache: the check itself is broken"
found="$(demo_entries "$headless/CMakeCache.txt" | tr '\n' ' ')"
[[ -z "$found" ]] || fail headless "the demo's dependencies were looked up: $found"
run headless headless-build.log cmake --build "$headless" -j2
if [[ -n "$(find "$headless" -type f \( -name 'libglad.a' -o -name 'libapp_ui.a' -o -name 'libapp_render.a' \))" ]]; then
  fail headless "glad, the UI or the renderer was built"
fi
# The command line is there (its windowless part), the game's targets are not.
targets="$(cmake --build "$headless" --target help)"
if grep -qwE 'glad|app_ui|app_render' <<<"$targets"; then
  fail headless "a target of the game exists"
fi
for target in app_core breakables; do
  grep -qw "$target" <<<"$targets" || fail headless "there is no $target target: the command line is not built"
done
# Every library test builds here without the demo; they run, but for the
# four slowest physics runs (about 28 s of the 2 cores), which the test
# suite has just run on the same code under the sanitizers.
run headless headless-ctest.log ctest --test-dir "$headless" --output-on-failure -j2 \
  -E '^test_(budget_fidelity|settle|stress_world|physics_budget)$'
ok "headless: no GLFW/ImGui/cglm/OpenGL lookup, no target of the game; $(grep -E 'tests passed' "$logs/headless-ctest.log")"
# Its install has the command line: fracture and sim run from it, and it
# loads no GLFW, GL or ImGui; play says in one line that there is no game.
headless_prefix="$tmp/prefix-headless"
run headless headless-install.log cmake --install "$headless" --prefix "$headless_prefix"
headless_exe="$headless_prefix/bin/breakables"
[[ -x "$headless_exe" ]] || fail headless "the headless install has no bin/breakables"
[[ ! -e "$headless_prefix/share/breakables/shaders" ]] || fail headless "the headless install has the game's shaders"
# GLU (authoring's tessellator) brings libOpenGL.so.0 in on Debian, never
# called; the program itself needs no GL library, and nothing loads GLFW,
# libGL (GLX) or ImGui.
needed() { readelf -d "$1" | sed -n 's/.*(NEEDED).*\[\(.*\)\]$/\1/p'; }
found="$(needed "$headless_exe" | grep -iE 'glfw|^libGL\.|^libGLX|^libOpenGL|imgui' | tr '\n' ' ' || true)"
[[ -z "$found" ]] || fail headless "the headless breakables links the game's libraries: $found"
found="$(ldd "$headless_exe" | grep -iE 'glfw|libGL\.so|libGLX|imgui' | tr '\n' ' ' || true)"
[[ -z "$found" ]] || fail headless "the headless breakables loads the game's libraries: $found"
grep -q 'libglfw' <<<"$(needed "$prefix/bin/breakables")" || fail headless "the demo's breakables links no GLFW: the check itself is broken"
run headless headless-fracture.log "$headless_exe" fracture --mesh cube --pieces 8 --json
python3 -c 'import json, sys; r = json.load(open(sys.argv[1])); sys.exit(0 if r["pieces_made"] == 8 and r["watertight"] else 1)' \
  "$logs/headless-fracture.log" || fail headless "fracture --mesh cube --pieces 8 --json: $(head -c 300 "$logs/headless-fracture.log")"
run headless headless-sim.log "$headless_exe" sim --scene wall --steps 60 --json
python3 -c 'import json, sys; r = json.load(open(sys.argv[1])); sys.exit(0 if r["scene"] == "wall" and r["nan"] is False else 1)' \
  "$logs/headless-sim.log" || fail headless "sim --scene wall --steps 60 --json: $(head -c 300 "$logs/headless-sim.log")"
if "$headless_exe" play >"$logs/headless-play.log" 2>&1; then fail headless "play succeeded in a build without the game"; fi
[[ "$(wc -l <"$logs/headless-play.log")" == 1 ]] && grep -q 'this build has no game' "$logs/headless-play.log" ||
  fail headless "play in a build without the game did not say so in one line: $(cat "$logs/headless-play.log")"
ok "headless: its installed breakables runs fracture (8 pieces) and sim (the wall, 60 steps) with no GLFW, GL or ImGui loaded; play says: $(cat "$logs/headless-play.log")"

# ---------------------------------------------------------------- no-bullet
# BK_BUILD_BULLET=OFF: an install without Bullet serves the runtime examples
# and refuses the bullet component with a message.
nobullet_prefix="$tmp/prefix-nobullet"
run no-bullet nobullet-configure.log cmake -S "$tmp/src" -B "$tmp/build-nobullet" -DCMAKE_BUILD_TYPE=Release \
  -DBK_BUILD_DEMO=OFF -DBK_BUILD_BULLET=OFF -DBK_BUILD_TESTS=OFF
found="$(grep -vE '^(//|#)' "$tmp/build-nobullet/CMakeCache.txt" | cut -d: -f1 | grep -E 'BULLET' | grep -v '^BK_BUILD_BULLET$' | head -n 3 | tr '\n' ' ' || true)"
[[ -z "$found" ]] || fail no-bullet "Bullet was looked up: $found"
run no-bullet nobullet-build.log cmake --build "$tmp/build-nobullet" -j2
run no-bullet nobullet-install.log cmake --install "$tmp/build-nobullet" --prefix "$nobullet_prefix"
for file in include/breakables/bullet.h lib/libbreakables-bullet.a lib/pkgconfig/breakables-bullet.pc \
  lib/cmake/breakables/breakables-bullet-targets.cmake; do
  [[ ! -e "$nobullet_prefix/$file" ]] || fail no-bullet "$file was installed without breakables::bullet"
done
for example in own_physics bake_and_load; do
  build="$tmp/examples-nobullet/$example"
  run no-bullet "nobullet-$example-configure.log" cmake -S "$tmp/src/examples/$example" -B "$build" \
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$nobullet_prefix"
  run no-bullet "nobullet-$example-build.log" cmake --build "$build"
done
"$tmp/examples-nobullet/own_physics/own_physics" >"$logs/own_physics_nobullet.out"
diff -u "$logs/own_physics.out" "$logs/own_physics_nobullet.out" >&2 || fail no-bullet "own_physics printed something else"
if cmake -S "$tmp/src/examples/headless_wall" -B "$tmp/examples-nobullet/headless_wall" -DCMAKE_PREFIX_PATH="$nobullet_prefix" \
  >"$logs/nobullet-headless_wall-configure.log" 2>&1; then
  fail no-bullet "headless_wall (COMPONENTS bullet) configured against an install without bullet"
fi
grep -q 'no bullet component' "$logs/nobullet-headless_wall-configure.log" ||
  fail no-bullet "find_package(breakables COMPONENTS bullet) failed without saying why: $(tail -n 5 "$logs/nobullet-headless_wall-configure.log")"
ok "no-bullet: BK_BUILD_BULLET=OFF installs no bullet files, serves own_physics and bake_and_load, refuses COMPONENTS bullet with a message"

# ---------------------------------------------------------------- h. relocated
# Only the prefix is left: the executable must find its data there.
mv "$tmp/src" "$tmp/src.moved"
mv "$tmp/build" "$tmp/build.moved"
export BREAKABLES_CACHE_DIR="$tmp/cache" # the game's mesh-tree cache, not the user's
exe="$prefix/bin/breakables"
run relocated fracture_help.log "$exe" fracture --help
run relocated fracture.log "$exe" fracture --mesh cube --pieces 64 --out "$tmp/x.mtree" --export-obj "$tmp/x.obj"
[[ -s "$tmp/x.mtree" && -s "$tmp/x.obj" ]] || fail relocated "fracture wrote no x.mtree or x.obj"
fragments="$(grep -c '^o fragment_' "$tmp/x.obj" || true)"
((fragments >= 64)) || fail relocated "x.obj has $fragments fragments, not 64"
# The bunny is an installed asset: found beside the executable, not in the (moved) source tree.
run relocated fracture_bunny.log "$exe" fracture --mesh bunny --pieces 8
ok "relocated: breakables fracture (cube into $fragments fragments; the installed bunny)"
run relocated play.log env LIBGL_ALWAYS_SOFTWARE=1 xvfb-run -a -s "-screen 0 1280x720x24" "$exe" play --scene wall \
  --frames 60 --autofire 2 --screenshot "$tmp/shot.png" --width 640 --height 360
grep -q '^frames 60, ' "$logs/play.log" || fail relocated "play printed no summary: $(cat "$logs/play.log")"
grep -q 'gl errors none' "$logs/play.log" || fail relocated "GL errors: $(grep -m1 '^frames' "$logs/play.log")"
[[ -s "$tmp/shot.png" ]] || fail relocated "no screenshot"
[[ "$(head -c 8 "$tmp/shot.png" | od -An -tx1 | tr -d ' \n')" == "89504e470d0a1a0a" ]] || fail relocated "shot.png is not a PNG"
ok "relocated: scripted play under xvfb-run ($(grep -m1 -oE '^frames [0-9]+, bodies [0-9]+ \(from [0-9]+\)' "$logs/play.log"), screenshot $(stat -c %s "$tmp/shot.png") bytes)"

finished=1
echo "check_install: all checks passed in $((SECONDS - start_seconds)) s"
