#!/usr/bin/env bash
# expect_stdout.sh REGEX COMMAND...: passes when COMMAND exits with status 0, writes nothing to
# stderr and exactly one line to stdout, matching REGEX (extended, the whole line).
set -u
regex="$1"
shift
out="$(mktemp)"
err="$(mktemp)"
"$@" >"$out" 2>"$err"
status=$?
lines=$(wc -l <"$out")
msg="$(cat "$out")"
errors="$(cat "$err")"
rm -f "$out" "$err"
if [ "$status" -ne 0 ]; then
  echo "FAIL: exit status $status (want 0) from: $*"
  echo "stderr: $errors"
  exit 1
fi
if [ -n "$errors" ]; then
  echo "FAIL: stderr not empty: $errors"
  exit 1
fi
if [ "$lines" -ne 1 ]; then
  echo "FAIL: $lines lines on stdout (want 1):"
  echo "$msg"
  exit 1
fi
if ! grep -Eqx -- "$regex" <<<"$msg"; then
  echo "FAIL: output does not match /$regex/: $msg"
  exit 1
fi
echo "ok: $msg"
