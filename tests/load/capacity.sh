#!/usr/bin/env bash
# The server's three capacity figures in one command (BENCHMARKS.md, "Lease latency and capacity"): merged
# results per second at 32 px tiles, lease p99, and server CPU per result, at 64 and 256
# simulated workers with 16 units per call, for one server or several compared run by run. Not
# part of CI (it takes minutes and its figures depend on the machine).
#
#   tests/load/capacity.sh BIN_DIR [SERVER_BIN...]
#
# BIN_DIR holds tessera-bench-merge and tessera_load_tests (the same ones measure every server);
# each SERVER_BIN (default BIN_DIR/tessera-server) runs in turn within each round (alternating).
# ROUNDS (default 3), WORKERS (default "64 256"), UNITS (the job sizes, default "4096 16384") and
# LOAD_TEST (default 1; 0 skips tessera_load_tests) change the sizes. SUMMARIZE=LOG prints the
# medians of the `server=...` lines of an earlier run's output LOG without running anything.
#
# Server CPU per result, three ways (tessera-bench-merge reads /proc/PID/stat):
#   listen s       the server's CPU at listening: the fixed cost of a start (exec, dynamic
#                  linking, store, gRPC set-up); not per result
#   run ms/res     CPU from the clock's start (every simulated worker registered) to the job's end,
#                  per result, at the larger job: what the run costs without the start
#   marginal ms/res  (CPU of the larger job's run - CPU of the smaller's) / (results difference):
#                  the cost of one more result, without anything a run pays once (the submit, the
#                  output at the end, long polls while the last units finish). This is the figure
#                  the 0.2 ms goal (printed at the end) is about.
# Rates and latencies are the larger job's. Every figure is a median over the rounds.
set -euo pipefail
bin=${1:?usage: capacity.sh BIN_DIR [SERVER_BIN...]}
shift
servers=("$@")
[ ${#servers[@]} -gt 0 ] || servers=("$bin/tessera-server")
rounds=${ROUNDS:-3}
workers=${WORKERS:-"64 256"}
units=${UNITS:-"4096 16384"}
load_test=${LOAD_TEST:-1}
for s in "${servers[@]}" "$bin/tessera-bench-merge"; do
  [ -x "$s" ] || { echo "capacity.sh: no executable $s" >&2; exit 2; }
done
read -r small large <<<"$units"
[ -n "${large:-}" ] && [ "$large" -gt "$small" ] ||
  { echo "capacity.sh: UNITS must name a smaller and a larger job size (got \"$units\")" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

echo "capacity.sh: $(date -u '+%F %T') UTC, $(nproc) CPUs, load $(cut -d' ' -f1-3 /proc/loadavg)"
if [ -n "${SUMMARIZE:-}" ]; then
  grep '^server=' "$SUMMARIZE" >"$tmp/bench" || true
  rounds=$(sed -n 's/.* round=\([0-9]*\) .*/\1/p' "$tmp/bench" | sort -n | tail -1)
  load_test=0
fi
for round in $( [ -n "${SUMMARIZE:-}" ] || seq 1 "$rounds"); do
  for n in $workers; do
    for u in $small $large; do
      for i in "${!servers[@]}"; do
        out=$("$bin/tessera-bench-merge" --server-bin "${servers[$i]}" --tiles 32 --workers "$n" \
          --per-call 16 --units "$u" --reps 1 --max-seconds 120 2>&1) || true
        line=$(grep '^    run: ' <<<"$out" | head -1 || true)
        if [ -z "$line" ]; then
          echo "round $round server $i N $n units $u: no result; its output:" >&2
          tail -5 <<<"$out" >&2
          continue
        fi
        echo "server=$i round=$round load=$(cut -d' ' -f1 /proc/loadavg) ${line#    run: }" |
          tee -a "$tmp/bench"
      done
    done
  done
  if [ "$load_test" = 1 ] && [ -x "$bin/tessera_load_tests" ]; then
    for n in $workers; do
      for i in "${!servers[@]}"; do
        out=$(TESSERA_LOAD_SERVER_BIN="${servers[$i]}" TESSERA_LOAD_WORKERS="$n" \
          "$bin/tessera_load_tests" --gtest_filter=Load.BatchedCallsNothingLostNoDeadlock 2>&1) || true
        line=$(grep '^\[load\]' <<<"$out" | head -1 || true)
        ok=$(grep -q '\[  PASSED  \] 1 test' <<<"$out" && echo passed || echo FAILED)
        echo "load server=$i round=$round N=$n load=$(cut -d' ' -f1 /proc/loadavg) $ok ${line:-no result}" |
          tee -a "$tmp/load"
      done
    done
  fi
done

echo
echo "medians over $rounds round(s); tile 32, 16 units per call; job sizes $small and $large units"
for i in "${!servers[@]}"; do
  for n in $workers; do
    awk -v srv="$i" -v n="$n" -v small="$small" -v large="$large" -v name="${servers[$i]}" '
      function kv(s, key) { s = " " s; return match(s, " " key "=[^ ]+") ? substr(s, RSTART + length(key) + 2, RLENGTH - length(key) - 2) : "" }
      function med(a, k,   i, j, t) {
        for (i = 1; i <= k; i++) for (j = i + 1; j <= k; j++) if (a[j] < a[i]) { t = a[i]; a[i] = a[j]; a[j] = t }
        return k == 0 ? "-" : (k % 2 ? a[(k + 1) / 2] : (a[k / 2] + a[k / 2 + 1]) / 2)
      }
      kv($0, "server") == srv && kv($0, "workers") == n {
        r = kv($0, "round"); ok = ok && kv($0, "checks") == "passed" && kv($0, "cut_off") == "0"
        if (kv($0, "units") + 0 >= large) {
          nl++; rate[nl] = kv($0, "merged_per_s") + 0; p99[nl] = kv($0, "lease_p99_ms") + 0
          later = kv($0, "lease_p99_later_ms"); if (later != "") { nlat++; p99l[nlat] = later + 0 }
          run[nl] = kv($0, "cpu_run_ms_per_res") + 0; listen[nl] = kv($0, "cpu_listen_s") + 0
          big_cpu[r] = kv($0, "cpu_run_s") + 0; big_acc[r] = kv($0, "accepted") + 0
        } else { small_cpu[r] = kv($0, "cpu_run_s") + 0; small_acc[r] = kv($0, "accepted") + 0 }
        rounds[r] = 1
      }
      BEGIN { ok = 1 }
      END {
        for (r in rounds) if ((r in big_cpu) && (r in small_cpu) && big_acc[r] > small_acc[r])
          marg[++nm] = 1000 * (big_cpu[r] - small_cpu[r]) / (big_acc[r] - small_acc[r])
        printf "server %d (%s) N %d: merged/s %s, lease p99 %s ms (after the first round %s ms), server CPU: listen %s s, run %s ms/res, marginal %s ms/res (%d round(s)); checks %s\n",
          srv, name, n, med(rate, nl), med(p99, nl), med(p99l, nlat), med(listen, nl), med(run, nl), med(marg, nm), nm, ok ? "passed" : "FAILED"
      }' "$tmp/bench"
  done
done
if [ -s "$tmp/load" ]; then
  echo "load test (tessera_load_tests, 20 jobs x 128 units, 16-px tiles, 16 per call):"
  cat "$tmp/load"
fi
echo "goals: >= 5000 results/s, lease p99 <= 20 ms, <= 0.2 ms of server CPU per result;"
echo "load at end: $(cut -d' ' -f1-3 /proc/loadavg)"
