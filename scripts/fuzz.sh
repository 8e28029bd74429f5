#!/usr/bin/env bash
# Builds the libFuzzer harnesses of tests/fuzz (clang, ASan+UBSan) in
# build-fuzz and runs each for SECONDS (default 60), one after the other.
#
#   scripts/fuzz.sh [SECONDS] [HARNESS...]     harnesses: fuzz_obj fuzz_mtree fuzz_bonds fuzz_fracture fuzz_gltf fuzz_import fuzz_seeds fuzz_runtime fuzz_journal fuzz_recording fuzz_state
#
# Each harness starts from its committed seeds and regressions
# (tests/fuzz/corpus/<harness>, tests/fuzz/regressions/<harness>), which it only
# reads; what it discovers goes to build-fuzz/corpus/<harness> and is reused by
# the next run. Exits 0 when every harness simply ran out of time, 1 when one
# failed (crash, sanitizer report, failed invariant, timeout, out of memory):
# the failing input is kept in build-fuzz/findings/<harness>/ and its path is
# printed, with the command that replays it.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo"

all_harnesses=(fuzz_obj fuzz_mtree fuzz_bonds fuzz_fracture fuzz_gltf fuzz_import fuzz_seeds fuzz_runtime fuzz_journal fuzz_recording fuzz_state)
seconds="${1:-60}"
if [[ $# -gt 0 ]]; then shift; fi
if ! [[ "$seconds" =~ ^[0-9]+$ ]] || ((10#$seconds < 1)); then
  echo "fuzz: SECONDS must be a whole number of seconds >= 1, got '$seconds'" >&2
  exit 2
fi
seconds=$((10#$seconds))
harnesses=("$@")
if ((${#harnesses[@]} == 0)); then harnesses=("${all_harnesses[@]}"); fi
for harness in "${harnesses[@]}"; do
  if [[ " ${all_harnesses[*]} " != *" $harness "* ]]; then
    echo "fuzz: unknown harness '$harness' (use ${all_harnesses[*]})" >&2
    exit 2
  fi
done

scripts/setup.sh

# Optimised with debug info: libFuzzer finds more per second than at -O0, and
# the sanitizer reports still name lines.
build=build-fuzz
cmake -S . -B "$build" -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DBK_FUZZ=ON -DBK_SANITIZE=OFF >/dev/null
build_start=$SECONDS
cmake --build "$build" -j"$(nproc)" --target "${harnesses[@]}" >/dev/null
echo "fuzz: built ${harnesses[*]} in $((SECONDS - build_start)) s"

# Per harness: inputs longer than this only slow the search (the harnesses
# refuse larger ones anyway), and one input may take this many seconds.
max_len() {
  case "$1" in
  fuzz_obj | fuzz_fracture | fuzz_seeds) echo 4096 ;;
  fuzz_runtime) echo 2048 ;; # a program of calls: a few hundred are plenty
  fuzz_import) echo 8192 ;; # the model seeds are up to about 5 KiB
  fuzz_gltf) echo 32768 ;; # the .glb/.gltf seeds are up to about 24 KiB
  *) echo 16384 ;; # the .mtree seeds are up to about 8 KiB
  esac
}
timeout_seconds=25

scratch="$(mktemp -d "${TMPDIR:-/tmp}/bk-fuzz.XXXXXX")"
trap 'rm -rf "$scratch"' EXIT

export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0"
export LSAN_OPTIONS="suppressions=$repo/scripts/lsan.supp"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"

failed=()
for harness in "${harnesses[@]}"; do
  corpus="$build/corpus/$harness"
  findings="$build/findings/$harness"
  log="$build/logs/$harness.log"
  mkdir -p "$corpus" "$findings" "$(dirname "$log")" "$scratch/$harness"
  seeds=("tests/fuzz/corpus/$harness")
  if [[ -d "tests/fuzz/regressions/$harness" ]]; then seeds+=("tests/fuzz/regressions/$harness"); fi
  status=0
  # assimp's leaks are suppressed by library name (scripts/lsan.supp), which
  # needs full stacks: its allocations go through libstdc++ without frame pointers.
  asan_options="$ASAN_OPTIONS"
  if [[ "$harness" == fuzz_import ]]; then asan_options+=":fast_unwind_on_malloc=0"; fi
  # The first directory receives new inputs; the committed ones after it are only read.
  ASAN_OPTIONS="$asan_options" BK_FUZZ_TMP="$scratch/$harness" "$build/$harness" -max_total_time="$seconds" -timeout="$timeout_seconds" \
    -rss_limit_mb=2048 -max_len="$(max_len "$harness")" -print_final_stats=1 \
    -artifact_prefix="$findings/" "$corpus" "${seeds[@]}" >"$log" 2>&1 || status=$?
  runs="$(grep -o 'Done [0-9]* runs in [0-9]* second(s)' "$log" | tail -n 1 || true)"
  if [[ -z "$runs" ]]; then
    runs="$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' | tail -n 1 || true)"
    runs="${runs:-0} runs before stopping"
  fi
  if ((status == 0)); then
    echo "fuzz: $harness: $runs, nothing found (corpus: $(find "$corpus" -type f | wc -l) inputs)"
    continue
  fi
  failed+=("$harness")
  echo "fuzz: $harness: FAILED (exit status $status) after $runs; log: $log" >&2
  grep -E '^(==[0-9]+==ERROR|SUMMARY|fuzz_[a-z]+: )|runtime error' "$log" | head -n 5 >&2 || true
  # libFuzzer names the input it saved: "Test unit written to <path>".
  grep -o 'Test unit written to .*' "$log" | sed 's/^Test unit written to //' | while read -r input; do
    echo "fuzz: $harness: failing input: $input (replay: $build/$harness $input)" >&2
  done
done

if ((${#failed[@]})); then
  echo "fuzz: failed: ${failed[*]}" >&2
  exit 1
fi
echo "fuzz: every harness ran ${seconds} s without a failure"
