#!/usr/bin/env bash
# The whole test suite, from a fresh Debian 12 machine: installs what is needed, builds a
# release build and runs every test, then builds with AddressSanitizer + UndefinedBehaviorSanitizer
# and runs every test but the long statistical ones (label "slow") and the fault-injection and
# load tests (labels "faults", "load": minutes on 2 cores even in release) under them; then
# runs the fuzz targets for a bounded time (fuzz/run.sh).
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
"$ROOT/scripts/install-deps.sh" --test

JOBS="${JOBS:-$(nproc)}"

echo "== release build"
BUILD_DIR="$ROOT/build" "$ROOT/scripts/build.sh" -DCMAKE_BUILD_TYPE=Release
echo "== release tests"
(cd "$ROOT/build" && ctest --output-on-failure -j "$JOBS" --timeout 1200)

if [ "${TESSERA_SKIP_SANITIZERS:-0}" != "1" ]; then
  echo "== sanitizer build (ASan + UBSan)"
  BUILD_DIR="$ROOT/build-asan" "$ROOT/scripts/build.sh" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTESSERA_SANITIZE=ON -DTESSERA_BUILD_BENCH=OFF -DTESSERA_BUILD_LONG_SUITES=OFF
  echo "== sanitizer tests"
  (cd "$ROOT/build-asan" && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
     LSAN_OPTIONS="suppressions=$ROOT/tests/sanitizers/lsan.supp:print_suppressions=0" \
     UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
     ctest --output-on-failure -j "$JOBS" --timeout 1200 -LE 'slow|faults|load')
fi
# Fuzzing (docs/reliability.md): every libFuzzer target for FUZZ_SECONDS (default 30) each.
if [ "${TESSERA_SKIP_FUZZ:-0}" != "1" ] && [ -x "$ROOT/fuzz/run.sh" ]; then
  echo "== fuzzing"
  "$ROOT/fuzz/run.sh" "${FUZZ_SECONDS:-30}"
fi
if [ "${TESSERA_SKIP_CONTAINERS:-0}" != "1" ]; then echo "== containers (deploy/test.sh)"; "$ROOT/deploy/test.sh"; else echo "== containers skipped (TESSERA_SKIP_CONTAINERS=1)"; fi
echo "== all tests passed"
