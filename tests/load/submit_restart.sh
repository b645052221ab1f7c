#!/usr/bin/env bash
# Submit time against spp, cancel, restart and delete on one tessera-server (BENCHMARKS.md,
# "Submit, cancel and delete against spp"). Not part of CI: it submits jobs of up to 2^30 spp.
#
#   tests/load/submit_restart.sh BIN_DIR [SPP...]      # default SPP: 2^20 2^25 2^28 2^30
#
# BIN_DIR holds tessera-server and tessera. For each SPP it submits the tiny test scene at 32x32
# (one tile), timing the submit; then restarts the server on the same database (time from exec
# to the port file, i.e. listening) and times each cancel and delete. Prints one line per job
# with the database size (file + WAL) after its submit. With KEEP_DB=FILE it also copies the
# database, as it was before the restart, to FILE (to time another server's start-up on it).
set -euo pipefail
bin=${1:?usage: submit_restart.sh BIN_DIR [SPP...]}
shift
spps=("$@")
[ ${#spps[@]} -gt 0 ] || spps=(1048576 33554432 268435456 1073741824)
here=$(cd "$(dirname "$0")/../.." && pwd)
scene=$here/tests/farm/data/tiny.json
tmp=$(mktemp -d)
server_pid=
cleanup() { [ -n "$server_pid" ] && kill "$server_pid" 2>/dev/null; wait 2>/dev/null; rm -rf "$tmp"; }
trap cleanup EXIT

start_server() {
  rm -f "$tmp/port"
  local t0=$(date +%s.%N)
  "$bin/tessera-server" --db "$tmp/farm.db" --grpc 127.0.0.1:0 --http 127.0.0.1:0 --insecure \
    --output-dir "$tmp/out" --port-file "$tmp/port" --max-units 4194304 >>"$tmp/server.log" 2>&1 &
  server_pid=$!
  while [ ! -s "$tmp/port" ]; do sleep 0.01; done
  local t1=$(date +%s.%N)
  export TESSERA_SERVER=127.0.0.1:$(tr -d '\n' <"$tmp/port")
  echo "server listening after $(echo "$t1 - $t0" | bc) s"
}
stop_server() { kill "$server_pid"; wait "$server_pid" || true; server_pid=; }
timed() { local t0=$(date +%s.%N); "$@" >/dev/null; echo "$(echo "$(date +%s.%N) - $t0" | bc)"; }
db_mb() { du -cb "$tmp"/farm.db* | tail -1 | awk '{printf "%.1f", $1 / 1e6}'; }

echo "load: $(cat /proc/loadavg)"
start_server
ids=()
for spp in "${spps[@]}"; do
  t0=$(date +%s.%N)
  id=$("$bin/tessera" submit "$scene" --width 32 --height 32 --spp "$spp" | awk '/^job / {print $2}')
  t=$(echo "$(date +%s.%N) - $t0" | bc)
  ids+=("$id")
  echo "spp $spp: job $id submit ${t} s, database $(db_mb) MB"
done
stop_server
echo "database before restart: $(db_mb) MB"
[ -z "${KEEP_DB:-}" ] || cp "$tmp/farm.db" "$KEEP_DB"
start_server
for id in "${ids[@]}"; do
  echo "job $id: cancel $(timed "$bin/tessera" cancel "$id") s, delete $(timed "$bin/tessera" delete "$id") s"
done
echo "database after deletes: $(db_mb) MB"
stop_server
echo "load: $(cat /proc/loadavg)"
