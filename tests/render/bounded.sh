#!/usr/bin/env bash
# bounded.sh KIB COMMAND...: runs COMMAND with its memory limited to KIB kibibytes, so a test
# shows that a hostile input is refused without allocating what it declares (a PLY header
# claiming 10^8 triangles would need 1.2 GB for the indices alone). Normally the limit is on
# virtual memory (ulimit -v). An AddressSanitizer build reserves terabytes of address space for
# its shadow memory and cannot start under that limit, so there the limit is ASan's own on the
# resident set (hard_rss_limit_mb), which ends the process as soon as it holds more. GCC links
# the ASan runtime as libasan.so, clang links it into the program: either way the program's
# dynamic symbols name __asan_init.
set -u
kib="$1"
shift
if nm -D "$1" 2>/dev/null | grep -q ' __asan_init$'; then
  export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}hard_rss_limit_mb=$((kib / 1024))"
else
  ulimit -v "$kib" || exit 2
fi
exec "$@"
