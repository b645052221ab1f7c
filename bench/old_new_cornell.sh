#!/usr/bin/env bash
# bench/old_new_cornell.sh OLD_BIN_DIR NEW_BIN_DIR [ROUNDS=5]: "a scene pays nothing for what it
# does not use" on the diffuse-only Cornell box, old and new builds alternating in one run.
# Each round runs, for old then new:
#   tessera-bench-diffuse scenes/cornell.json --integrator full 256x256 8 spp, 1 thread
#       -> its render time (s; the renderer's trace_path, scene loading left out)
#   tessera-worker render scenes/cornell.json 256x256 16 spp, THREADS 1 and 2
#       -> the k samples/s it prints (render only; its default integrator)
# Prints one line per measurement: what, round, build, value, 1-minute load average; then the
# medians per (what, build) and new / old.
set -euo pipefail
OLD=$1; NEW=$2; ROUNDS=${3:-5}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "== $(date -u '+%Y-%m-%d %H:%M UTC'), load before: $(cat /proc/loadavg)"
for r in $(seq 1 "$ROUNDS"); do
  for b in old new; do
    dir=$OLD; [ $b = new ] && dir=$NEW
    t=$("$dir/tessera-bench-diffuse" scenes/cornell.json --integrator full --width 256 --height 256 \
        --spp 8 --runs 1 | awk '/^median/{print $2}')
    echo "diffuse_s $r $b $t $(cut -d' ' -f1 /proc/loadavg)" | tee -a "$out/all"
    for th in 1 2; do
      ks=$("$dir/tessera-worker" render scenes/cornell.json --width 256 --height 256 --spp 16 \
          --threads $th -o "$out/x.exr" 2>&1 | awk '/^rendered/{for (i = 2; i < NF; ++i) if ($(i + 1) ~ /^(k|M)$/ && $(i + 2) ~ /^samples\/s/) {print ($(i + 1) == "M" ? $i * 1000 : $i); exit}}')
      echo "ksps_t$th $r $b $ks $(cut -d' ' -f1 /proc/loadavg)" | tee -a "$out/all"
    done
  done
done
echo "== medians (load after: $(cat /proc/loadavg))"
python3 - "$out/all" <<'PY'
import statistics, sys
rows = [l.split() for l in open(sys.argv[1])]
for what in dict.fromkeys(r[0] for r in rows):
    med = {b: statistics.median(float(r[3]) for r in rows if r[0] == what and r[2] == b)
           for b in ("old", "new")}
    rng = {b: (min(float(r[3]) for r in rows if r[0] == what and r[2] == b),
               max(float(r[3]) for r in rows if r[0] == what and r[2] == b)) for b in ("old", "new")}
    print(f"{what}: old {med['old']:.4g} ({rng['old'][0]:.4g}-{rng['old'][1]:.4g}), "
          f"new {med['new']:.4g} ({rng['new'][0]:.4g}-{rng['new'][1]:.4g}), new/old {med['new']/med['old']:.3f}")
PY
