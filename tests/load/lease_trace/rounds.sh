#!/usr/bin/env bash
# Where a lease's time goes, in the server (BENCHMARKS.md, "Issue 14: lease latency (branch
# farm10)"). Not part of CI. Build each server with its instrumentation patch applied
# (main-5f0f79f.patch on main at 5f0f79f, farm10.patch on branch farm10; neither is meant to be
# merged): the patched server appends p50/p90/p99/max of its lease and upload-group timings to
# /tmp/farm10_trace.txt at shutdown. Then:
#
#   tests/load/lease_trace/rounds.sh BENCH_BIN SERVER_A SERVER_B
#
# runs tessera-bench-merge --tiles 32 --per-call 16 --units 16384 against each server in turn
# within each round (alternating), ROUNDS (default 3) rounds at WORKERS (default "64 256").
set -u
bench=${1:?usage: rounds.sh BENCH_BIN SERVER_A SERVER_B}
shift
for round in $(seq 1 "${ROUNDS:-3}"); do
  for n in ${WORKERS:-64 256}; do
    for s in "$@"; do
      rm -f /tmp/farm10_trace.txt
      line=$("$bench" --server-bin "$s" --tiles 32 --workers "$n" --per-call 16 --units 16384 \
        --reps 1 --max-seconds 120 2>&1 | grep "run:")
      echo "round=$round N=$n server=$s load=$(cut -d' ' -f1 /proc/loadavg) ${line#    run: }"
      grep TRACE /tmp/farm10_trace.txt 2>/dev/null | sed 's/^/    /'
    done
  done
done
