#!/usr/bin/env bash
# The main job, from a fresh Debian 12 machine: installs what is needed, builds, and renders
# scenes/cornell.json. With the farm built (tessera-server, tessera), it starts a server and two
# workers on loopback, submits the job through the CLI and writes the image the farm merged;
# the processes are stopped at the end. Output: out/cornell.png and out/cornell.exr.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
cd "$ROOT"
"$ROOT/scripts/install-deps.sh"
# Only the three programs the demo runs (scripts/test.sh builds the rest, tests included).
BUILD_DIR="$ROOT/build" TARGETS="tessera-worker tessera-server tessera" \
  "$ROOT/scripts/build.sh" -DCMAKE_BUILD_TYPE=Release
BIN="$ROOT/build/bin"
SPP="${SPP:-256}"
mkdir -p out

if [ ! -x "$BIN/tessera-server" ] || [ ! -x "$BIN/tessera" ]; then
  echo "demo: rendering locally (this build has no farm)"
  "$BIN/tessera-worker" render scenes/cornell.json --spp "$SPP" -o out/cornell.exr -o out/cornell.png
  echo "demo: wrote out/cornell.exr and out/cornell.png"
  exit 0
fi

RUN_DIR="$(mktemp -d)"
pids=()
cleanup() {
  for pid in "${pids[@]}"; do kill -TERM "$pid" 2>/dev/null || true; done
  wait 2>/dev/null || true
  rm -rf "$RUN_DIR"
}
trap cleanup EXIT

# The server picks a free port and writes it to a file once it listens.
"$BIN/tessera-server" --grpc 127.0.0.1:0 --http 127.0.0.1:0 --db "$RUN_DIR/tessera.db" \
  --output-dir "$RUN_DIR/outputs" --port-file "$RUN_DIR/port" --http-port-file "$RUN_DIR/http-port" \
  >"$RUN_DIR/server.log" 2>&1 &
pids+=($!)
for _ in $(seq 300); do
  [ -s "$RUN_DIR/port" ] && break
  kill -0 "${pids[0]}" 2>/dev/null || { cat "$RUN_DIR/server.log"; exit 1; }
  sleep 0.1
done
[ -s "$RUN_DIR/port" ] || { echo "demo: the server did not start"; cat "$RUN_DIR/server.log"; exit 1; }
GRPC="127.0.0.1:$(cat "$RUN_DIR/port")"
for i in 1 2; do
  "$BIN/tessera-worker" --server "$GRPC" --threads 1 --cache "$RUN_DIR/cache$i" --name "demo-$i" \
    >"$RUN_DIR/worker$i.log" 2>&1 &
  pids+=($!)
done
echo "demo: server on $GRPC (dashboard: http://127.0.0.1:$(cat "$RUN_DIR/http-port")/), two workers;" \
  "submitting scenes/cornell.json at $SPP spp"
"$BIN/tessera" --server "$GRPC" submit scenes/cornell.json --spp "$SPP" -o out/cornell.exr
"$BIN/tessera" --server "$GRPC" list
"$BIN/tessera" --server "$GRPC" workers
JOB="$("$BIN/tessera" --server "$GRPC" list --json | python3 -c 'import json,sys; d=json.load(sys.stdin); print((d["jobs"] if isinstance(d, dict) else d)[0]["id"])')"
"$BIN/tessera" --server "$GRPC" get "$JOB" -o out/cornell.png
echo "demo: wrote out/cornell.exr and out/cornell.png (merged by the farm)"
