#!/usr/bin/env bash
# Debug build with AddressSanitizer/UBSan, then runs the test suite. The
# sanitizer build uses clang: its UBSan reports what GCC's misses (an offset
# applied to a null pointer, for one); scripts/check_install.sh builds with
# the default compiler (GCC), so both compilers' warnings stay errors.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo"

scripts/setup.sh

export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export LSAN_OPTIONS="suppressions=$repo/scripts/lsan.supp"

# -O1, as the sanitizers' authors advise: reports keep their lines and
# frames (no inlining across files, frame pointers kept), and the suite runs
# in well under half the time of -O0. Assertions stay on (Debug).
cmake -S . -B build-debug -DCMAKE_BUILD_TYPE=Debug -DBK_SANITIZE=ON \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_C_FLAGS_DEBUG="-g -O1" -DCMAKE_CXX_FLAGS_DEBUG="-g -O1"
cmake --build build-debug -j"$(nproc)"
# LeakSanitizer's tracer (clang 14's) now and then crashes while it stops a
# process with many threads (the game under Mesa's llvmpipe) to check for
# leaks: "LeakSanitizer has encountered a fatal error", not a finding. When
# that is in the log, the failed tests run once more, alone; any other
# failure fails as it is.
if ! ctest --test-dir build-debug --output-on-failure -j2; then
  # The tracer's message is in the test's log, or in the stderr file of the
  # game a test ran (build-debug/test_tmp).
  if grep -qs "LeakSanitizer has encountered a fatal error" build-debug/Testing/Temporary/LastTest.log \
    build-debug/test_tmp/*stderr*; then
    echo "test: LeakSanitizer's tracer crashed in a test above; running the failed tests once more" >&2
    ctest --test-dir build-debug --output-on-failure --rerun-failed
  else
    exit 1
  fi
fi
# What an install gives a user: builds a copy of the tree (with and without
# the demo and Bullet), installs it, builds and runs the examples against it,
# and runs the installed game with the source and build trees moved away.
scripts/check_install.sh
