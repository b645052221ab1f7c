#!/usr/bin/env bash
# bench/bench_rays_alternating.sh OLD/tessera-bench-rays NEW/tessera-bench-rays SCENE...: old and new
# tessera-bench-rays alternating, 5 rounds per scene (scenes/SCENE.json, --seconds 2 --threads 1
# --spp 16); prints scene, round, build, samples per CPU-second (M: the tool's rays per CPU-second
# x samples/s / rays/s) and the load average.
set -euo pipefail
OLD=$1; NEW=$2; shift 2
for scene in "$@"; do
  for r in 1 2 3 4 5; do
    for b in old new; do
      bin=$OLD; [ $b = new ] && bin=$NEW
      out=$($bin scenes/$scene.json --seconds 2 --threads 1 --spp 16)
      sps=$(echo "$out" | awk '/^renderer: /{s=$2; r=$5} /^renderer per CPU-second \(all/{c=$7} END{printf "%.4f", c*s/r}')
      echo "$scene $r $b $sps $(cut -d' ' -f1 /proc/loadavg)"
    done
  done
done
