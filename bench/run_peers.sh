#!/bin/sh
# Runs the peer measurements of BENCHMARKS.md in one go and logs them with the machine's load.
# Usage: sh bench/run_peers.sh [LOGFILE]   (from the repository root; default out/peers.log)
# With WAIT_QUIET=1 it first waits (up to 30 min) for the 1-minute load average to fall below 0.5,
# and gives up (exit 2, nothing measured) if it does not: other work on a 2-core machine distorts
# every timing.
set -eu
LOG=${1:-out/peers.log}
# PY: a Python with Mitsuba 3 (bench/README.md); default the repository's .venv-bench.
PY=${PY:-.venv-bench/bin/python}
mkdir -p out "$(dirname "$LOG")"
if [ "${WAIT_QUIET:-0}" = 1 ]; then
  i=0
  while [ "$(cut -d' ' -f1 /proc/loadavg | awk '{print ($1 < 0.5)}')" != 1 ] && [ $i -lt 180 ]; do
    sleep 10; i=$((i + 1))
  done
  if [ "$(cut -d' ' -f1 /proc/loadavg | awk '{print ($1 < 0.5)}')" != 1 ]; then
    echo "machine not quiet after 30 min (load $(cat /proc/loadavg)); nothing measured" >&2
    exit 2
  fi
fi
{
  echo "== $(date -u '+%Y-%m-%d %H:%M:%S UTC'), $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"
  echo "load before: $(cat /proc/loadavg)"
  echo "== Mitsuba 256 spp, depth 8, 2 threads, 5 runs"
  $PY bench/mitsuba_cbox.py --spp 256 --max-depth 8 --threads 2 --runs 5 \
      --ref tests/data/reference/cbox/ref_depth8.exr -o out/mitsuba_cbox_256.exr
  echo "load: $(cat /proc/loadavg)"
  echo "== Mitsuba 1024 spp, depth 8, 2 threads, 1 run"
  $PY bench/mitsuba_cbox.py --spp 1024 --max-depth 8 --threads 2 --runs 1 \
      --ref tests/data/reference/cbox/ref_depth8.exr -o out/mitsuba_cbox_1024.exr
  echo "load: $(cat /proc/loadavg)"
  if command -v pathtracer >/dev/null; then
    echo "== Embree pathtracer 256 spp, path length 7, 2 threads, 3 runs"
    python3 bench/cornell_obj.py --outdir out/embree
    for r in 1 2 3; do
      ( cd out/embree && /usr/bin/time -f "run $r: %e s wall, %U s user, %S s sys" \
          pathtracer -i cornell.obj $(cat cornell.args) --size 256 256 --spp 256 \
          --max-path-length 7 --threads 2 -o cornell256.ppm >/dev/null )
    done
    echo "load after: $(cat /proc/loadavg)"
  fi
} 2>&1 | tee "$LOG"
