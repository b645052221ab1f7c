#!/usr/bin/env bash
# expect_error.sh REGEX COMMAND...: passes when COMMAND exits with status 1 (a handled error,
# not a crash or a signal) and writes exactly one line to stderr, matching REGEX.
set -u
regex="$1"
shift
err="$(mktemp)"
"$@" >/dev/null 2>"$err"
status=$?
lines=$(wc -l <"$err")
msg="$(cat "$err")"
rm -f "$err"
if [ "$status" -ne 1 ]; then
  echo "FAIL: exit status $status (want 1) from: $*"
  echo "stderr: $msg"
  exit 1
fi
if [ "$lines" -ne 1 ]; then
  echo "FAIL: $lines lines on stderr (want 1):"
  echo "$msg"
  exit 1
fi
if ! grep -Eq -- "$regex" <<<"$msg"; then
  echo "FAIL: message does not match /$regex/: $msg"
  exit 1
fi
echo "ok: $msg"
