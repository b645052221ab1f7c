#!/usr/bin/env bash
# tessera-server maps no OpenImageIO library when it starts (server/lazy_image_io.cpp): its
# shared libraries (ldd) leave out OpenImageIO and the ~260 libraries it brings, which were
# most of start-up's CPU (BENCHMARKS.md, "Start-up: where the time goes (branch dash8)").
#   server_start_libraries.sh SERVER_BIN
set -euo pipefail
bin=${1:?usage: server_start_libraries.sh SERVER_BIN}
libs=$(ldd "$bin")
count=$(wc -l <<<"$libs")
echo "$bin: $count shared libraries at start"
if grep -i openimageio <<<"$libs"; then
  echo "FAIL: $bin loads OpenImageIO at start (an image function outside server/lazy_image_io.cpp?)" >&2
  exit 1
fi
if [ "$count" -gt 120 ]; then
  echo "FAIL: $bin loads $count shared libraries at start (66 on Debian 12 in December 2026)" >&2
  exit 1
fi
echo "PASS"
