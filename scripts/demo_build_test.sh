#!/usr/bin/env bash
# demo_build_test.sh: scripts/demo.sh builds only the programs it runs (tessera-worker,
# tessera-server, tessera), not the tests. Runs the demo with `cmake` and `ninja` replaced by
# stubs that record their arguments (ninja then stops the demo), and checks what ninja was asked
# to build. Needs the build dependencies installed (install-deps.sh then does nothing).
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
STUBS="$(mktemp -d)"
trap 'rm -rf "$STUBS"' EXIT
printf '#!/bin/sh\nexit 0\n' >"$STUBS/cmake"
printf '#!/bin/sh\necho "$@" >"%s/ninja-args"\nexit 3\n' "$STUBS" >"$STUBS/ninja"
chmod +x "$STUBS/cmake" "$STUBS/ninja"
PATH="$STUBS:$PATH" "$ROOT/scripts/demo.sh" >/dev/null 2>&1 || true
[ -f "$STUBS/ninja-args" ] || { echo "FAIL: demo.sh never ran ninja"; exit 1; }
got="$(cat "$STUBS/ninja-args")"
want="-C $ROOT/build tessera-worker tessera-server tessera"
if [ "$got" != "$want" ]; then
  echo "FAIL: demo.sh ran 'ninja $got', want 'ninja $want'"
  exit 1
fi
echo "ok: ninja $got"
