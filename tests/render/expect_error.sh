#!/usr/bin/env bash
# expect_error.sh [--status N] REGEX COMMAND...: passes when COMMAND exits with status N
# (default 1, a handled error; 2 is a usage error; never a crash or a signal) and writes exactly
# one line to stderr, matching REGEX.
set -u
want=1
if [ "$1" = "--status" ]; then
  want="$2"
  shift 2
fi
regex="$1"
shift
err="$(mktemp)"
"$@" >/dev/null 2>"$err"
status=$?
lines=$(wc -l <"$err")
msg="$(cat "$err")"
rm -f "$err"
if [ "$status" -ne "$want" ]; then
  echo "FAIL: exit status $status (want $want) from: $*"
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
