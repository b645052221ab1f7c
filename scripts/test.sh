#!/usr/bin/env bash
# The whole test suite, from a fresh Debian 12 machine: installs what is needed, builds a
# release build and runs the long tests in it (the statistical ones, label "slow", and the
# fault-injection and load tests, labels "faults" and "load": minutes on 2 cores even in
# release), then builds with AddressSanitizer + UndefinedBehaviorSanitizer and runs every other
# test under them; then runs the fuzz targets for a bounded time (fuzz/run.sh). The container
# deployment test (deploy/test.sh) runs beside all that from the release build on.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"

# Wall time per phase, printed when the script ends (passed or failed), so that a CI log's tail
# says where the time went.
PHASE="" PHASE_START=$SECONDS TIMES=""
phase() {
  if [ -n "$PHASE" ]; then TIMES+="$(printf '%6d s  %s' $((SECONDS - PHASE_START)) "$PHASE")"$'\n'; fi
  PHASE="$1" PHASE_START=$SECONDS
  [ -n "$1" ] && echo "== $1"
  return 0
}
CONTAINERS_PID=""
finish() {
  local status=$?
  # A failed phase leaves the container test running in the background: stop it (its own trap
  # removes what it started).
  if [ -n "$CONTAINERS_PID" ]; then kill "$CONTAINERS_PID" 2>/dev/null; wait "$CONTAINERS_PID" 2>/dev/null; fi
  phase ""
  printf "== time per phase (exit %d, %d s in all)\n%s" $status $SECONDS "$TIMES"
}
trap finish EXIT

phase "install dependencies"
"$ROOT/scripts/install-deps.sh" --test

JOBS="${JOBS:-$(nproc)}"

phase "release build"
# With the sanitizer pass to come, the release build leaves out the test binaries only that pass
# runs (cmake/TesseraTests.cmake): they were about half of its compile time.
SHORT=OFF
if [ "${TESSERA_SKIP_SANITIZERS:-0}" = "1" ]; then SHORT=ON; fi
# Its libraries compile a few files per translation unit too (TESSERA_UNITY_LIBS, as in the
# sanitizer pass): the headers they share are parsed once per batch, not once per file.
BUILD_DIR="$ROOT/build" "$ROOT/scripts/build.sh" -DCMAKE_BUILD_TYPE=Release -DTESSERA_BUILD_SHORT_SUITES=$SHORT -DTESSERA_UNITY_LIBS=ON
# Each test runs once: the long ones (labels slow, faults, load: statistical renders, fault
# injection, load) in the release build, where they take minutes, and every other test in the
# sanitizer build below, which checks more. Without sanitizers, the release build runs them all.
# The container test needs only the release binaries, and spends most of its two minutes
# installing packages, building images and waiting on containers rather than computing: it runs
# in the background from here, beside the release tests and the sanitizer pass, and is waited
# for at the end.
if [ "${TESSERA_SKIP_CONTAINERS:-0}" != "1" ]; then
  CONTAINERS_LOG="$ROOT/build/containers.log"
  CONTAINERS_BEGAN=$SECONDS
  "$ROOT/deploy/test.sh" >"$CONTAINERS_LOG" 2>&1 &
  CONTAINERS_PID=$!
fi
LONG='slow|faults|load'
phase "release tests"
if [ "${TESSERA_SKIP_SANITIZERS:-0}" != "1" ]; then
  (cd "$ROOT/build" && ctest --output-on-failure -j "$JOBS" --timeout 1200 -L "$LONG")
else
  (cd "$ROOT/build" && ctest --output-on-failure -j "$JOBS" --timeout 1200)
fi

if [ "${TESSERA_SKIP_SANITIZERS:-0}" != "1" ]; then
  phase "sanitizer build (ASan + UBSan)"
  # clang 14 (installed for the fuzz targets anyway): it builds this pass from nothing in 2,016 s
  # of CPU where GCC 12 took 3,023 s (BENCHMARKS.md, "CI time"), and its UBSan checks more
  # (float-to-integer overflow among others). The release build stays GCC's. The unit-test
  # binaries compile 8 files per translation unit (cmake/TesseraTests.cmake): 423 s of CPU
  # instead of 869 s; so do the libraries that allow it (CMakeLists.txt, TESSERA_UNITY_LIBS).
  BUILD_DIR="$ROOT/build-asan" "$ROOT/scripts/build.sh" -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTESSERA_SANITIZE=ON -DTESSERA_BUILD_BENCH=OFF -DTESSERA_BUILD_LONG_SUITES=OFF -DTESSERA_TEST_SHARDS=ON -DTESSERA_UNITY_TESTS=ON -DTESSERA_UNITY_LIBS=ON
  # The unit-test binaries run as a few gtest shards each (cmake/TesseraTests.cmake): one
  # process per test spent most of this phase in the dynamic loader.
  phase "sanitizer tests"
  (cd "$ROOT/build-asan" && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
     LSAN_OPTIONS="suppressions=$ROOT/tests/sanitizers/lsan.supp:print_suppressions=0" \
     UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
     ctest --output-on-failure -j "$JOBS" --timeout 1200 -LE "$LONG")
fi
# Fuzzing (docs/reliability.md): every libFuzzer target for FUZZ_SECONDS (default 30) each.
if [ "${TESSERA_SKIP_FUZZ:-0}" != "1" ] && [ -x "$ROOT/fuzz/run.sh" ]; then
  phase "fuzzing (build and run)"
  "$ROOT/fuzz/run.sh" "${FUZZ_SECONDS:-30}"
fi
if [ -n "$CONTAINERS_PID" ]; then
  phase "containers (deploy/test.sh, in the background since the release build)"
  containers_status=0
  wait "$CONTAINERS_PID" || containers_status=$?
  CONTAINERS_PID=""
  cat "$CONTAINERS_LOG"
  echo "== containers: exit $containers_status, $((SECONDS - CONTAINERS_BEGAN)) s since they began"
  [ "$containers_status" -eq 0 ] || exit "$containers_status"
else
  echo "== containers skipped (TESSERA_SKIP_CONTAINERS=1)"
fi
echo "== all tests passed"
