#!/usr/bin/env bash
# tessera-server and the tessera client map no OpenImageIO library when they start
# (core/image/image_module.h): their shared libraries (ldd) leave out OpenImageIO and the ~250
# libraries it brings, which were most of the server's start-up CPU (BENCHMARKS.md, "Server
# start-up time") and about 0.2 s of CPU for every client command (BENCHMARKS.md, "The farm's
# overhead on one job").
#   start_libraries.sh BIN
set -euo pipefail
bin=${1:?usage: start_libraries.sh BIN}
libs=$(ldd "$bin")
count=$(wc -l <<<"$libs")
echo "$bin: $count shared libraries at start"
if grep -i openimageio <<<"$libs"; then
  echo "FAIL: $bin loads OpenImageIO at start (an OpenImageIO call outside core/image/oiio_image_io.cpp and core/image/oiio_image_check.cpp?)" >&2
  exit 1
fi
if [ "$count" -gt 120 ]; then
  echo "FAIL: $bin loads $count shared libraries at start (server 66, client 59 on Debian 12 in December 2026)" >&2
  exit 1
fi
echo "PASS"
