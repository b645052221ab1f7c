#!/usr/bin/env bash
# expect_image.sh OUT COMMAND...: passes when COMMAND exits with status 0 and writes the
# non-empty file OUT (removed first, so an old one does not count).
set -u
out="$1"
shift
rm -f "$out"
"$@"
status=$?
if [ "$status" -ne 0 ]; then
  echo "FAIL: exit status $status from: $*"
  exit 1
fi
if [ ! -s "$out" ]; then
  echo "FAIL: $out was not written by: $*"
  exit 1
fi
echo "ok: $out"
