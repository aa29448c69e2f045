#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer, in build-asan/:
# the core and the CLI (no PCL adapter, no benchmarks, no Python module), -O1 to compile faster;
# IFEM_TEST_QUICK skips the corpus's files over 1 MB (3–5× slower under ASan), every small and
# degenerate input still runs. About 10 min of 2 cores to build, 3 min to run. Run it before a
# submission; CI runs the fuzz harnesses under the same sanitizers (docs/decisions.md D-117).
#
#   scripts/sanitize.sh [ctest arguments, e.g. -R Intrinsic]
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1 -DNDEBUG" \
  -DIFEM_SANITIZE=ON -DIFEM_BUILD_BENCHMARKS=OFF -DIFEM_WITH_PCL=OFF -DIFEM_BUILD_PYTHON=OFF >/dev/null
cmake --build build-asan -j"$(nproc)"
IFEM_TEST_QUICK=1 ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir build-asan --output-on-failure -j"$(nproc)" "$@"
