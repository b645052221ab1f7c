#!/usr/bin/env bash
# Start-up time on a large store (BENCHMARKS.md, "Server start-up time"). Not part of CI.
#
#   tests/load/restart_large.sh BIN_DIR [SERVER_BIN...]
#
# Makes a store of 2,097,152 units: a 32x32 job of 2^31-1 spp (submitted with --max-units
# raised, then cancelled), 2,097,152 unit rows written into it with the sqlite3 CLI, and 384 MB
# of bundle rows (a real store of that many units was a 515 MB file plus its WAL). Then, for
# each SERVER_BIN (default BIN_DIR/tessera-server), alternating, 3 rounds: the time from exec to
# listening (the port file) after a clean stop (SIGTERM), and after a SIGKILL.
set -euo pipefail
bin=${1:?usage: restart_large.sh BIN_DIR [SERVER_BIN...]}
shift
servers=("$@")
[ ${#servers[@]} -gt 0 ] || servers=("$bin/tessera-server")
here=$(cd "$(dirname "$0")/../.." && pwd)
scene=$here/tests/farm/data/tiny.json
tmp=$(mktemp -d)
server_pid=
cleanup() { [ -n "$server_pid" ] && kill -9 "$server_pid" 2>/dev/null; wait 2>/dev/null; rm -rf "$tmp"; }
trap cleanup EXIT

# start_server SERVER_BIN: sets `elapsed` to the seconds from exec to the port file.
start_server() {
  rm -f "$tmp/port"
  local t0 t1
  t0=$(date +%s.%N)
  "$1" --db "$tmp/farm.db" --grpc 127.0.0.1:0 --http 127.0.0.1:0 --insecure \
    --output-dir "$tmp/out" --port-file "$tmp/port" --max-units 4194304 >>"$tmp/server.log" 2>&1 &
  server_pid=$!
  while [ ! -s "$tmp/port" ]; do
    kill -0 "$server_pid" 2>/dev/null || { echo "server exited; log:" >&2; tail "$tmp/server.log" >&2; exit 1; }
    sleep 0.01
  done
  t1=$(date +%s.%N)
  export TESSERA_SERVER=127.0.0.1:$(tr -d '\n' <"$tmp/port")
  elapsed=$(echo "$t1 - $t0" | bc)
}
stop_server() { kill "-$1" "$server_pid"; wait "$server_pid" || true; server_pid=; }
db_mb() { du -cb "$tmp"/farm.db* | tail -1 | awk '{printf "%.1f", $1 / 1e6}'; }

start_server "${servers[0]}"
id=$("$bin/tessera" submit "$scene" --width 32 --height 32 --spp 2147483647 | awk '/^job / {print $2}')
"$bin/tessera" cancel "$id" >/dev/null
stop_server TERM
sqlite3 "$tmp/farm.db" <<SQL
PRAGMA foreign_keys = ON;
BEGIN;
WITH RECURSIVE b(n) AS (SELECT 0 UNION ALL SELECT n + 1 FROM b WHERE n + 1 < 2097152)
INSERT INTO units (job_id, tile, batch, state) SELECT $id, 0, n, 'cancelled' FROM b;
WITH RECURSIVE p(n) AS (SELECT 0 UNION ALL SELECT n + 1 FROM p WHERE n + 1 < 384)
INSERT INTO bundles (sha256, scene_file, data, size_bytes, created_unix_ms)
  SELECT printf('%064d', n), 'padding', randomblob(1000000), 1000000, 0 FROM p;
COMMIT;
PRAGMA wal_checkpoint(TRUNCATE);
SQL
echo "store: $(sqlite3 "$tmp/farm.db" 'SELECT COUNT(*) FROM units') unit rows, $(db_mb) MB"
echo "load: $(cat /proc/loadavg)"
for round in 1 2 3; do
  for s in "${servers[@]}"; do
    start_server "$s"   # takes whatever the previous stop left
    stop_server TERM
    start_server "$s"
    clean=$elapsed
    stop_server KILL
    start_server "$s"
    killed=$elapsed
    stop_server TERM
    echo "round $round $s: after a clean stop ${clean} s, after SIGKILL ${killed} s to listening"
  done
done
echo "load: $(cat /proc/loadavg)"
