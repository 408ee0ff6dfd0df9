#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The sanitizer stages of CI (.ci/run runs them after the README's two commands), each in a
# build directory of its own and built with clang++ (the README's build is g++'s, so CI
# builds the tree with both compilers), in Release (-O1 with assertions compiled about as
# long on the heaviest files and would run the suites slower):
#   asan  AddressSanitizer + UndefinedBehaviorSanitizer (any report fails the test) build of
#         the libraries, the tool, the test suites and the fuzz harnesses (-DGRAPHSLAM_FUZZ=ON,
#         which brings these sanitizers); ctest -L unit, -L cli (not the dataset label: the
#         public files are what the Release run is for) and -L fuzz (every harness replays
#         its regression inputs, then fuzzes for GRAPHSLAM_FUZZ_SECONDS, 60 by default).
#   tsan  ThreadSanitizer build of the suites that hold the threaded tests (the target
#         graphslam_tsan_suites of tests/CMakeLists.txt); ctest -L tsan (the concurrency
#         tests and the threaded reading, linearisation and observability tests).
# Each stage prints its wall time. Usage: tools/ci_sanitizers.sh [asan|tsan]...  (default both)
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=${GRAPHSLAM_CI_JOBS:-2}
cxx=${GRAPHSLAM_CI_SANITIZER_CXX:-clang++}
# The Python package is left out: its tests run in the README's build (an instrumented
# extension would need the sanitizer runtime preloaded into the interpreter).
common=(-DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER="$cxx" -DGRAPHSLAM_BUILD_BENCH=OFF
        -DGRAPHSLAM_PYTHON=OFF)
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0
export TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1

timed() {
  local name=$1 start=$SECONDS
  shift
  echo "== sanitizers: $name"
  "$@"
  echo "== sanitizers: $name took $((SECONDS - start)) s"
}

asan() {
  timed "asan configure and build" bash -c "cmake -S . -B build-asan ${common[*]} \
    -DGRAPHSLAM_FUZZ=ON -DGRAPHSLAM_FUZZ_SECONDS=${GRAPHSLAM_FUZZ_SECONDS:-60} > /dev/null && \
    cmake --build build-asan -j$jobs"
  timed "asan ctest -L unit" ctest --test-dir build-asan -j"$jobs" -L unit --output-on-failure
  timed "asan ctest -L cli" ctest --test-dir build-asan -j"$jobs" -L cli -LE dataset --output-on-failure
  timed "asan ctest -L fuzz" ctest --test-dir build-asan -j"$jobs" -L fuzz --output-on-failure
}

tsan() {
  timed "tsan configure and build" bash -c "cmake -S . -B build-tsan ${common[*]} \
    -DGRAPHSLAM_SANITIZE=thread -DGRAPHSLAM_BUILD_APPS=OFF > /dev/null && \
    cmake --build build-tsan -j$jobs --target graphslam_tsan_suites"
  timed "tsan ctest -L tsan" ctest --test-dir build-tsan -L tsan --output-on-failure
}

stages=("$@")
[ ${#stages[@]} -gt 0 ] || stages=(asan tsan)
for s in "${stages[@]}"; do
  case "$s" in
    asan) asan ;;
    tsan) tsan ;;
    *) echo "tools/ci_sanitizers.sh: unknown stage '$s' (asan or tsan)" >&2; exit 2 ;;
  esac
done
