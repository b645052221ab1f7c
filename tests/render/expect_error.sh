#!/usr/bin/env bash
# expect_error.sh [--status N] REGEX COMMAND...: passes when COMMAND exits with status N
# (default 1, a handled error; 2 is a usage error; never a crash or a signal) and writes exactly
# one line to stderr, matching REGEX.
# expect_error.sh --stdout REGEX COMMAND...: the same for a command that succeeds (status 0, or
# --status N before --stdout) and writes exactly one line to stdout, matching REGEX, and nothing
# to stderr (`--version`).
set -u
want=1
if [ "$1" = "--status" ]; then
  want="$2"
  shift 2
fi
stream=stderr
if [ "$1" = "--stdout" ]; then
  stream=stdout
  [ "$want" = 1 ] && want=0
  shift
fi
regex="$1"
shift
out="$(mktemp)"
err="$(mktemp)"
"$@" >"$out" 2>"$err"
status=$?
if [ "$stream" = stdout ]; then
  if [ -s "$err" ]; then
    echo "FAIL: stderr not empty: $(cat "$err")"
    rm -f "$out" "$err"
    exit 1
  fi
  mv "$out" "$err"
fi
rm -f "$out"
lines=$(wc -l <"$err")
msg="$(cat "$err")"
rm -f "$err"
if [ "$status" -ne "$want" ]; then
  echo "FAIL: exit status $status (want $want) from: $*"
  echo "$stream: $msg"
  exit 1
fi
if [ "$lines" -ne 1 ]; then
  echo "FAIL: $lines lines on $stream (want 1):"
  echo "$msg"
  exit 1
fi
if ! grep -Eq -- "$regex" <<<"$msg"; then
  echo "FAIL: message does not match /$regex/: $msg"
  exit 1
fi
echo "ok: $msg"
