#!/usr/bin/env bash
# Builds the libFuzzer harnesses (tests/fuzz) with clang in build-fuzz/ (idempotent), then runs
# each one for SECONDS on a scratch copy of its seed corpus. Fails on any crash, leak, timeout,
# out-of-memory or sanitizer report; prints per harness the executions and the coverage.
#
#   scripts/fuzz.sh [SECONDS_PER_HARNESS] [HARNESS...]    (default 60 s, every harness)
#
# Findings are copied to tests/fuzz/crashes/<harness>/ (crash-/leak-/timeout-/oom-<hash>);
# reproduce one with: build-fuzz/tests/fuzz/<harness> tests/fuzz/crashes/<harness>/<file>
# Corpora grow in build-fuzz/corpus/<harness>/ (kept between runs; delete to start over from
# the seeds). FUZZ_JOBS=N runs N harnesses at a time (default 1). FUZZ_O0_LIBS=OFF builds the
# libraries at FUZZ_OPT (default -O1) instead of -O0 (D-261): faster long runs, slower build.
# Known open UBSan reports are suppressed through tests/fuzz/ubsan.supp; IFEM_FUZZ_STRICT=1
# reports them too.
# FUZZ_RUNS=N stops each harness after N inputs (SECONDS stays an upper bound) and FUZZ_SEED=S
# fixes libFuzzer's random seed: from the committed seeds that makes a run repeatable, which is
# what CI uses (a green CI cannot turn red by luck); longer random runs find the new bugs.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
[ $# -gt 0 ] && shift
build="build-fuzz"
all=(obj off ply stl xyz values matrix_market signpost pipeline curves integer)
harnesses=("${@:-${all[@]}}")

# -O1 -g, assertions on (no NDEBUG): Eigen's index checks are worth having while fuzzing. The
# libraries but their readers are instrumented at -O0 to keep CI's build short (D-261);
# FUZZ_O0_LIBS=OFF builds them at FUZZ_OPT (default -O1) too, for long hunts.
opt=${FUZZ_OPT:--O1}
CC=clang CXX=clang++ cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_CXX_FLAGS_RELEASE="$opt -g" -DCMAKE_C_FLAGS_RELEASE="$opt -g" -DIFEM_FUZZ=ON \
  -DIFEM_FUZZ_O0_LIBS="${FUZZ_O0_LIBS:-ON}" \
  -DIFEM_BUILD_TESTS=OFF -DIFEM_BUILD_BENCHMARKS=OFF -DIFEM_WITH_PCL=OFF -DIFEM_BUILD_PYTHON=OFF >/dev/null
cmake --build "$build" -j"${FUZZ_BUILD_JOBS:-2}" --target ifem_fuzzers
# The library units tests/fuzz/CMakeLists.txt compiles uninstrumented (IFEM_FUZZ_UNREACHED) must
# stay out of every harness: the linker's maps say which archive members each one pulled in.
reached=$(cat "$build"/tests/fuzz/fuzz_*.map | grep -o -F -f "$build/tests/fuzz/unreached_members.txt" |
  sort -u || true)
if [ -n "$reached" ]; then
  echo "fuzz: a harness links units built without instrumentation; take them off IFEM_FUZZ_UNREACHED" \
    "in tests/fuzz/CMakeLists.txt:" $reached >&2
  exit 1
fi
# ... and every other (instrumented) unit must be linked by some harness: an unreachable one only
# costs an instrumented compile.
unused=$(for lib in "$build"/*/libifem_*.a; do
  name=$(basename "$lib")
  ar t "$lib" | while read -r member; do
    entry="$name($member)"
    grep -q -F -x "$entry" "$build/tests/fuzz/unreached_members.txt" && continue
    grep -q -F "$entry" "$build"/tests/fuzz/fuzz_*.map || echo "$entry"
  done
done)
if [ -n "$unused" ]; then
  echo "fuzz: no harness links these instrumented units; add them to IFEM_FUZZ_UNREACHED in" \
    "tests/fuzz/CMakeLists.txt:" $unused >&2
  exit 1
fi

# The seed files of each harness: its tests/fuzz/seeds/ folder and the test meshes of its
# format (the pipeline reads every mesh format; libFuzzer cuts spot.obj to -max_len).
seeds_of() {
  case "$1" in
    pipeline) echo tests/fuzz/seeds/{obj,off,ply,stl,xyz}/* tests/data/*.{obj,ply} ;;
    obj|ply) echo tests/fuzz/seeds/"$1"/* tests/data/*."$1" ;;
    *) echo tests/fuzz/seeds/"$1"/* ;;
  esac
}
dict_of() {
  case "$1" in
    obj|off|ply|stl|signpost|matrix_market|curves|integer) [ -f "tests/fuzz/$1.dict" ] && echo "-dict=tests/fuzz/$1.dict" ;;
    pipeline) echo "-dict=tests/fuzz/pipeline.dict" ;;
  esac
  return 0
}

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
# tests/fuzz/ubsan.supp: known open reports (each with its reproducer), unless IFEM_FUZZ_STRICT=1.
supp=""
[ "${IFEM_FUZZ_STRICT:-0}" = 1 ] || supp=":suppressions=$PWD/tests/fuzz/ubsan.supp"
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1$supp}
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-1}

run_one() {
  local h=$1 bin="$build/tests/fuzz/fuzz_$1" corpus="$build/corpus/$1" art="$build/artifacts/$1"
  local log="$build/logs/fuzz_$1.log"
  rm -rf "$art"
  mkdir -p "$corpus" "$art" "$build/logs"
  # shellcheck disable=SC2046
  cp -n $(seeds_of "$h") "$corpus"/
  local status=0
  # shellcheck disable=SC2046
  local repeatable=()
  [ -n "${FUZZ_RUNS:-}" ] && repeatable+=(-runs="$FUZZ_RUNS")
  [ -n "${FUZZ_SEED:-}" ] && repeatable+=(-seed="$FUZZ_SEED")
  "$bin" "$corpus" $(dict_of "$h") "${repeatable[@]}" -max_total_time="$seconds" -max_len=65536 \
    -rss_limit_mb=2048 -malloc_limit_mb=2048 -timeout=10 -print_final_stats=1 \
    -artifact_prefix="$art/" >"$log" 2>&1 || status=$?
  local execs cov ft
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | cut -d' ' -f2)
  ft=$(grep -o 'ft: [0-9]*' "$log" | tail -1 | cut -d' ' -f2)
  if [ "$status" != 0 ] || [ -n "$(find "$art" -type f)" ]; then
    mkdir -p "tests/fuzz/crashes/$h"
    cp "$art"/* "tests/fuzz/crashes/$h"/ 2>/dev/null || true
    echo "fuzz: $h FAILED (exit $status) after ${execs:-?} execs; log $log, inputs in tests/fuzz/crashes/$h/"
    grep -m1 -E 'ERROR: |runtime error|fuzz: ' "$log" || tail -5 "$log"
    return 1
  fi
  echo "fuzz: $h ok: ${execs:-?} execs (limit ${FUZZ_RUNS:-none} runs, ${seconds} s), cov ${cov:-?} edges, ft ${ft:-?}, corpus $(find "$corpus" -type f | wc -l) files"
}

failed=0
jobs=${FUZZ_JOBS:-1}
pids=()
for h in "${harnesses[@]}"; do
  if [ "$jobs" -gt 1 ]; then
    run_one "$h" & pids+=($!)
    if [ ${#pids[@]} -ge "$jobs" ]; then wait "${pids[0]}" || failed=1; pids=("${pids[@]:1}"); fi
  else
    run_one "$h" || failed=1
  fi
done
for p in "${pids[@]}"; do wait "$p" || failed=1; done
if [ "$failed" != 0 ]; then echo "fuzz: FAILED (see above)"; exit 1; fi
echo "fuzz: all ${#harnesses[@]} harnesses clean"
