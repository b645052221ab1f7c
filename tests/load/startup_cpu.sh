#!/usr/bin/env bash
# CPU time a tessera-server has used when it starts listening (BENCHMARKS.md, "Server
# start-up time"). Not part of CI. A load-independent figure: the wall time to
# listening on a loaded machine is mostly waiting for a CPU.
#
#   tests/load/startup_cpu.sh ROUNDS SERVER_BIN...
#
# For each round and each SERVER_BIN (alternating): a new store, exec to the port file (the
# server writes it last, after both listeners are up), then the CPU time of the process so far:
# utime+stime of /proc/PID/stat (10 ms ticks; threads that have ended included) and the sum over
# its live threads of /proc/PID/task/*/schedstat (ns; finer, but blind to a thread that has ended,
# such as the server's image module loader). Prints one line per start, then the medians.
set -euo pipefail
rounds=${1:?usage: startup_cpu.sh ROUNDS SERVER_BIN...}
shift
[ $# -gt 0 ] || { echo "usage: startup_cpu.sh ROUNDS SERVER_BIN..." >&2; exit 2; }
tmp=$(mktemp -d)
pid=
cleanup() { [ -n "$pid" ] && kill -9 "$pid" 2>/dev/null; wait 2>/dev/null; rm -rf "$tmp"; }
trap cleanup EXIT
tick=$(getconf CLK_TCK)
echo "load: $(cat /proc/loadavg)"
for round in $(seq "$rounds"); do
  for s in "$@"; do
    rm -rf "$tmp/db" && mkdir -p "$tmp/db"
    t0=$(date +%s.%N)
    "$s" --db "$tmp/db/farm.db" --grpc 127.0.0.1:0 --http 127.0.0.1:0 --output-dir "$tmp/out" \
      --port-file "$tmp/db/port" >>"$tmp/server.log" 2>&1 &
    pid=$!
    while [ ! -s "$tmp/db/port" ]; do
      kill -0 "$pid" 2>/dev/null || { echo "server exited; log:" >&2; tail "$tmp/server.log" >&2; exit 1; }
      sleep 0.002
    done
    t1=$(date +%s.%N)
    read -r -a stat < <(sed 's/.*) //' "/proc/$pid/stat")  # fields from 3 (state) on
    ticks=$((stat[11] + stat[12]))                          # utime, stime (fields 14, 15)
    ns=$(cat /proc/"$pid"/task/*/schedstat | awk '{s += $1} END {print s}')
    kill -TERM "$pid"; wait "$pid" || true; pid=
    printf '%s round %d: wall %.3f s, cpu %.3f s (stat), %.3f s (schedstat)\n' "$s" "$round" \
      "$(echo "$t1 - $t0" | bc)" "$(echo "$ticks / $tick" | bc -l)" "$(echo "$ns / 1000000000" | bc -l)"
  done
done | tee "$tmp/lines"
for s in "$@"; do
  wall=$(grep -F "$s round" "$tmp/lines" | awk '{print $5}' | sort -g | awk '{v[NR]=$1} END {print v[int((NR+1)/2)]}')
  cpu=$(grep -F "$s round" "$tmp/lines" | awk '{print $8}' | sort -g | awk '{v[NR]=$1} END {print v[int((NR+1)/2)]}')
  live=$(grep -F "$s round" "$tmp/lines" | awk '{print $11}' | sort -g | awk '{v[NR]=$1} END {print v[int((NR+1)/2)]}')
  echo "$s: median wall $wall s, median cpu $cpu s (stat; live threads' schedstat $live s) over $rounds starts"
done
echo "load: $(cat /proc/loadavg)"
