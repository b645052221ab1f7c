#!/usr/bin/env bash
# The farm's overhead (BENCHMARKS.md): the same job rendered by `tessera-worker render` and by
# tessera-server + one tessera-worker on the same machine, RUNS times each, alternating; prints
# the median wall times, the overhead, and the result bytes sent per work unit.
#
#   bench/farm_overhead.sh            # 512x512, 256 spp Cornell box, 5 runs each
#   RUNS=3 SIZE=256 SPP=64 bench/farm_overhead.sh
#
# Wall time of the farm run: `tessera submit --wait -o OUT.exr` from submission to the image on
# disk (bundle upload, scheduling, every unit's round trip, merge, EXR+PNG written by the server,
# EXR downloaded). The local run: `tessera-worker render -o OUT.exr`.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
BIN="${BIN:-$ROOT/build/bin}"
RUNS="${RUNS:-5}"
SIZE="${SIZE:-512}"
SPP="${SPP:-256}"
SCENE="${SCENE:-$ROOT/scenes/cornell.json}"
OPTS=(--width "$SIZE" --height "$SIZE" --spp "$SPP")

for b in tessera-server tessera-worker tessera; do
  [ -x "$BIN/$b" ] || { echo "farm_overhead: $BIN/$b not built (set BIN)" >&2; exit 1; }
done

WORK="$(mktemp -d)"
SERVER_PID=""
WORKER_PID=""
cleanup() {
  [ -n "$WORKER_PID" ] && kill "$WORKER_PID" 2>/dev/null || true
  [ -n "$SERVER_PID" ] && kill "$SERVER_PID" 2>/dev/null || true
  wait 2>/dev/null || true
  rm -rf "$WORK"
}
trap cleanup EXIT

"$BIN/tessera-server" --grpc 127.0.0.1:0 --http 127.0.0.1:0 --port-file "$WORK/port" --db "$WORK/farm.db" \
  --output-dir "$WORK/outputs" >"$WORK/server.log" 2>&1 &
SERVER_PID=$!
for _ in $(seq 600); do [ -s "$WORK/port" ] && break; sleep 0.05; done
ADDR="127.0.0.1:$(cat "$WORK/port")"
"$BIN/tessera-worker" --server "$ADDR" --cache "$WORK/cache" --name bench >"$WORK/worker.log" 2>&1 &
WORKER_PID=$!

now() { date +%s.%N; }
elapsed() { python3 -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.3f}')" "$1" "$2"; }

local_times=()
farm_times=()
for i in $(seq "$RUNS"); do
  t0=$(now)
  "$BIN/tessera-worker" render "$SCENE" "${OPTS[@]}" -q -o "$WORK/local.exr" >/dev/null
  t1=$(now)
  local_times+=("$(elapsed "$t0" "$t1")")
  t0=$(now)
  "$BIN/tessera" --server "$ADDR" submit "$SCENE" "${OPTS[@]}" -o "$WORK/farm.exr" 2>/dev/null
  t1=$(now)
  farm_times+=("$(elapsed "$t0" "$t1")")
  echo "run $i: local ${local_times[-1]} s, farm ${farm_times[-1]} s" >&2
done

kill -TERM "$WORKER_PID"
wait "$WORKER_PID" || true
WORKER_PID=""
per_unit="$(grep -o '([0-9]* per unit)' "$WORK/worker.log" | tail -1 | tr -dc '0-9')"
units="$("$BIN/tessera" --server "$ADDR" status 1 --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["counters"]["units_total"])')"

python3 - "$RUNS" "$SIZE" "$SPP" "$per_unit" "$units" "${local_times[@]}" "${farm_times[@]}" <<'PY'
import statistics, sys
runs, size, spp, per_unit, units = int(sys.argv[1]), sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5]
times = [float(t) for t in sys.argv[6:]]
local, farm = statistics.median(times[:runs]), statistics.median(times[runs:])
print(f"job: {size}x{size}, {spp} spp, {units} units per job, {runs} runs each")
print(f"tessera-worker render : median {local:.3f} s  (runs: {' '.join(f'{t:.3f}' for t in times[:runs])})")
print(f"server + 1 worker     : median {farm:.3f} s  (runs: {' '.join(f'{t:.3f}' for t in times[runs:])})")
print(f"farm overhead         : {100.0 * (farm - local) / local:+.1f} %")
print(f"result bytes per unit : {per_unit} (zstd-compressed accumulation, gRPC framing excluded)")
PY
