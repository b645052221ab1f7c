#!/usr/bin/env bash
# bench/old_new_render.sh OLD_BIN_DIR NEW_BIN_DIR [ROUNDS=5] [SCENE...]: two builds of the
# renderer alternating in one run, on the scenes given (default scenes/cornell.json), from the
# repository root. Each round runs, for old then new:
#   tessera-bench-diffuse scenes/cornell.json --integrator full 256x256 8 spp, 1 thread, when
#       both builds have it and the Cornell box is among the scenes ("a scene pays nothing for
#       what it does not use") -> its render time (s; trace_path, scene loading left out)
#   tessera-worker render SCENE 256x256 16 spp, THREADS 1 and 2
#       -> the k samples/s it prints (render only; its default integrator)
# Prints one line per measurement: what, round, build, value, 1-minute load average; then the
# medians per (what, build) with their ranges, and new / old.
set -euo pipefail
OLD=$1; NEW=$2; ROUNDS=${3:-5}
shift $(( $# < 3 ? $# : 3 ))
SCENES=("$@")
[ ${#SCENES[@]} -gt 0 ] || SCENES=(scenes/cornell.json)
DIFFUSE=0
if [ -x "$OLD/tessera-bench-diffuse" ] && [ -x "$NEW/tessera-bench-diffuse" ] &&
   printf '%s\n' "${SCENES[@]}" | grep -qx 'scenes/cornell.json'; then DIFFUSE=1; fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "== $(date -u '+%Y-%m-%d %H:%M UTC'), load before: $(cat /proc/loadavg)"
for r in $(seq 1 "$ROUNDS"); do
  for b in old new; do
    dir=$OLD; [ $b = new ] && dir=$NEW
    if [ $DIFFUSE = 1 ]; then
      t=$("$dir/tessera-bench-diffuse" scenes/cornell.json --integrator full --width 256 --height 256 \
          --spp 8 --runs 1 | awk '/^median/{print $2}')
      echo "diffuse_s $r $b $t $(cut -d' ' -f1 /proc/loadavg)" | tee -a "$out/all"
    fi
    for scene in "${SCENES[@]}"; do
      name=$(basename "${scene%.*}")
      for th in 1 2; do
        ks=$("$dir/tessera-worker" render "$scene" --width 256 --height 256 --spp 16 \
            --threads $th -o "$out/x.exr" 2>&1 | awk '/^rendered/{for (i = 2; i < NF; ++i) if ($(i + 1) ~ /^(k|M)$/ && $(i + 2) ~ /^samples\/s/) {print ($(i + 1) == "M" ? $i * 1000 : $i); exit}}')
        echo "ksps_${name}_t$th $r $b $ks $(cut -d' ' -f1 /proc/loadavg)" | tee -a "$out/all"
      done
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
