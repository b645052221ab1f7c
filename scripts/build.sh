#!/usr/bin/env bash
# Configures and builds Tessera into BUILD_DIR (default build/). Extra arguments go to CMake.
# TARGETS (space-separated) builds only those targets and what they need; unset, everything
# (tests included).
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
BUILD_DIR="${BUILD_DIR:-$ROOT/build}"
# The short test suites are built unless the arguments say otherwise (scripts/test.sh's release
# pass leaves them out), also in a build folder an earlier scripts/test.sh configured without them.
cmake -S "$ROOT" -B "$BUILD_DIR" -G Ninja -DTESSERA_BUILD_SHORT_SUITES=ON "$@" >/dev/null
# shellcheck disable=SC2086  # TARGETS is a list
ninja -C "$BUILD_DIR" ${TARGETS:-}
