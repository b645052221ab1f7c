#!/usr/bin/env bash
# The server's memory on the largest image its default limits accept (BENCHMARKS.md, "Server
# memory on the largest image"). Not part of CI: on 2 cores it takes minutes and
# writes gigabytes (16,384 results of a 64-px tile, each into the WAL and then the file).
#
#   tests/load/largest_image.sh BIN_DIR [SCENE] [SIZE]     # BOUND_GIB=2: the peak allowed
#
# BIN_DIR holds tessera-server, tessera-worker and tessera. Starts a server with its default
# limits (--max-pixels 8192 x 8192, --merge-cache-mb 1024) and one worker, submits SCENE
# (default scenes/cornell.json) at SIZE x SIZE (default 8192) and 1 spp, and samples the
# server's resident memory (VmRSS) every half second with the job's state. Prints the peak
# (VmHWM) while results merge and over the whole job (a preview PNG is fetched half way, and the
# output EXR and PNG are written at the end), and checks that every unit was merged exactly
# once, that the image reached the disk and that the peak stayed within BOUND_GIB (default 2:
# docs/farm.md, "The server's memory"). Exits non-zero when one of them fails.
set -euo pipefail
bin=${1:?usage: largest_image.sh BIN_DIR [SCENE] [SIZE]}
here=$(cd "$(dirname "$0")/../.." && pwd)
scene=${2:-$here/scenes/cornell.json}
size=${3:-8192}
bound_gib=${BOUND_GIB:-2}
for b in tessera-server tessera-worker tessera; do
  [ -x "$bin/$b" ] || { echo "largest_image.sh: $bin/$b not built" >&2; exit 2; }
done
tmp=$(mktemp -d)
server_pid= worker_pid=
cleanup() {
  [ -n "$worker_pid" ] && kill "$worker_pid" 2>/dev/null
  [ -n "$server_pid" ] && kill "$server_pid" 2>/dev/null
  wait 2>/dev/null
  rm -rf "$tmp"
}
trap cleanup EXIT

kib() { awk -v k="$1" '$1 == k":" {print $2}' "/proc/$server_pid/status"; }
gib() { awk -v k="$1" 'BEGIN {printf "%.2f", k / 1048576}'; }

echo "load: $(cat /proc/loadavg)"
"$bin/tessera-server" --db "$tmp/farm.db" --grpc 127.0.0.1:0 --http 127.0.0.1:0 --insecure \
  --output-dir "$tmp/out" --port-file "$tmp/port" >"$tmp/server.log" 2>&1 &
server_pid=$!
while [ ! -s "$tmp/port" ]; do
  kill -0 "$server_pid" 2>/dev/null || { cat "$tmp/server.log" >&2; exit 1; }
  sleep 0.05
done
export TESSERA_SERVER=127.0.0.1:$(tr -d '\n' <"$tmp/port")
echo "server idle: VmRSS $(gib "$(kib VmRSS)") GiB"
"$bin/tessera-worker" --server "$TESSERA_SERVER" --cache "$tmp/cache" --name largest \
  >"$tmp/worker.log" 2>&1 &
worker_pid=$!

t0=$(date +%s)
id=$("$bin/tessera" submit "$scene" --width "$size" --height "$size" --spp 1 | awk '/^job / {print $2}')
[ -n "$id" ] || { echo "largest_image.sh: the submit was refused" >&2; exit 1; }
echo "job $id: ${size}x${size}, 1 spp, submitted"

# Half-second samples: seconds, VmRSS (KiB), state, merged units.
merging_peak=0 state= last_report=0 preview_done=
while :; do
  json=$("$bin/tessera" status "$id" --json)
  read -r state merged total < <(python3 -c 'import json, sys
j = json.load(sys.stdin)
print(j["state"], j["counters"]["results_merged"], j["counters"]["units_total"])' <<<"$json")
  rss=$(kib VmRSS)
  now=$(( $(date +%s) - t0 ))
  if [ "$merged" != "$total" ] && [ "$rss" -gt "$merging_peak" ]; then merging_peak=$rss; fi
  # Once, about half way: a preview (`tessera get` of the running job, the PNG encoded from the
  # merged tiles).
  if [ -z "$preview_done" ] && (( merged * 2 >= total )) && [ "$merged" != "$total" ]; then
    "$bin/tessera" get "$id" -o "$tmp/preview.png" >/dev/null 2>&1
    preview_done=$merged
    echo "  ${now} s: a preview at $merged of $total merged ($(du -m "$tmp/preview.png" | cut -f1) MB),"\
      "VmHWM now $(gib "$(kib VmHWM)") GiB"
  fi
  if (( now - last_report >= 15 )); then
    echo "  ${now} s: $state, $merged of $total merged, VmRSS $(gib "$rss") GiB"
    last_report=$now
  fi
  case "$state" in done|failed|cancelled) break ;; esac
  sleep 0.5
done
end=$(( $(date +%s) - t0 ))
hwm=$(kib VmHWM)
echo "job $id $state after $end s: $merged of $total units merged"
echo "server peak while results merged (VmRSS sampled every 0.5 s): $(gib "$merging_peak") GiB"
echo "server peak over the whole job (VmHWM, the output's EXR and PNG included): $(gib "$hwm") GiB"
echo "server now: VmRSS $(gib "$(kib VmRSS)") GiB"
find "$tmp/out" -type f -printf '  %f %s\n' | awk '{printf "  output %s: %.1f MB\n", $1, $2 / 1e6}'
echo "load: $(cat /proc/loadavg)"
[ "$state" = done ] && [ "$merged" = "$total" ] && [ "$total" -gt 0 ] ||
  { echo "largest_image.sh: the job did not end done with every unit merged" >&2; exit 1; }
[ -n "$(find "$tmp/out" -name '*.exr')" ] || { echo "largest_image.sh: no output EXR" >&2; exit 1; }
awk -v k="$hwm" -v b="$bound_gib" 'BEGIN {exit !(k <= b * 1048576)}' ||
  { echo "largest_image.sh: the server's peak $(gib "$hwm") GiB is over the bound of $bound_gib GiB" >&2; exit 1; }
echo "within the bound of $bound_gib GiB"
