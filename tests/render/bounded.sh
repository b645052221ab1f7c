#!/usr/bin/env bash
# bounded.sh KIB COMMAND...: runs COMMAND with its virtual memory limited to KIB kibibytes
# (ulimit -v), so a test shows that a hostile input is refused without allocating what it
# declares (a PLY header claiming 10^8 triangles would need 1.2 GB for the indices alone).
set -u
ulimit -v "$1" || exit 2
shift
exec "$@"
