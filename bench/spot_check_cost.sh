#!/bin/bash
# The server's CPU per merged result with and without spot checks: one job (tiny.json of
# tests/farm/data at 128x128, 8-px tiles, 64 batches of 1 spp: 16,384 units) on 3 local workers, for
# OLD_BIN (a build before --verify: submitted without it), then NEW_BIN with --verify 0 and with
# --verify RATE, alternating, ROUNDS times. The server's user+system CPU from the workers'
# start to the job's end, over the results merged.
# usage: bench/spot_check_cost.sh OLD_BIN NEW_BIN [ROUNDS=5] [RATE=0.01]
set -euo pipefail
OLD=$1 NEW=$2 ROUNDS=${3:-5} RATE=${4:-0.01}
SCENE="$(cd "$(dirname "$0")/.." && pwd)/tests/farm/data/tiny.json"

one_job() {  # BIN VERIFY(none|rate) TAG
  local bin=$1 verify=$2 tag=$3 dir addr spid ticks0 ticks merged
  dir=$(mktemp -d)
  "$bin/tessera-server" --grpc 127.0.0.1:0 --port-file "$dir/port" --http 127.0.0.1:0 \
    --db "$dir/farm.db" --output-dir "$dir/out" >"$dir/server.log" 2>&1 &
  spid=$!
  for _ in $(seq 100); do [ -s "$dir/port" ] && break; sleep 0.1; done
  addr=127.0.0.1:$(cat "$dir/port")
  local workers=()
  for i in 0 1 2; do
    "$bin/tessera-worker" --server "$addr" --threads 1 --cache "$dir/cache" --name "w$i" \
      >"$dir/w$i.log" 2>&1 &
    workers+=($!)
  done
  sleep 1
  local stat; read -r -a stat <"/proc/$spid/stat"; ticks0=$((stat[13] + stat[14]))
  local flags=(); [ "$verify" != none ] && flags=(--verify "$verify")
  "$bin/tessera" --server "$addr" submit "$SCENE" --width 128 --height 128 --tile 8 --spp 64 \
    --batch 1 "${flags[@]}" --wait -o "$dir/out.exr" >/dev/null 2>&1
  read -r -a stat <"/proc/$spid/stat"; ticks=$((stat[13] + stat[14] - ticks0))
  merged=$("$bin/tessera" --server "$addr" status 1 --json | python3 -c 'import json, sys
j = json.load(sys.stdin)
print(j["counters"]["results_merged"], j.get("units_checked", 0))')
  kill "${workers[@]}" "$spid" 2>/dev/null || true
  wait 2>/dev/null || true
  rm -rf "$dir"
  python3 -c "t = $ticks / $(getconf CLK_TCK); m, c = '$merged'.split()
print('$tag: server CPU %.2f s, %s merged, %s checked, %.4f ms a result'
      % (t, m, c, 1000 * t / int(m)))"
}

for r in $(seq "$ROUNDS"); do
  one_job "$OLD" none "old round $r"
  one_job "$NEW" 0 "new --verify 0 round $r"
  one_job "$NEW" "$RATE" "new --verify $RATE round $r"
done
