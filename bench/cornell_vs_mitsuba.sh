#!/usr/bin/env bash
# Time to reach Mitsuba's 256-spp RMSE on the Cornell box (depth 8), both renderers on the same
# 2 cores in the same run. Tessera runs before and after Mitsuba so load drifts show; medians are
# over all of its runs.
# Usage: bench/cornell_vs_mitsuba.sh [TESSERA_SPP=64] [RUNS=5]   (repository root; needs
# build/bin/tessera-worker and the .venv-bench of bench/README.md; PY=/path/to/python overrides
# the venv's interpreter, e.g. another checkout's .venv-bench/bin/python)
# Each Tessera run uses its own seed (1..RUNS); the RMSE of every run is printed with the median.
set -euo pipefail
SPP=${1:-64}
RUNS=${2:-5}
REF=tests/data/reference/cbox/ref_depth8.exr
PY=${PY:-.venv-bench/bin/python}
mkdir -p out
echo "== $(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) cores,$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"
echo "load before: $(cat /proc/loadavg)"
times=()
render_times=()
rmses=()
tessera_runs() {
  for r in $(seq "$RUNS"); do
    start=$(date +%s.%N)
    line=$(build/bin/tessera-worker render scenes/cornell.json --spp "$SPP" --max-depth 8 --threads 2 \
      --seed "$r" -q -o out/tessera_cbox.exr 2>&1 | grep '^rendered')
    end=$(date +%s.%N)
    times+=("$(echo "$end - $start" | bc)")
    # "rendered WxH, N spp in T s: ..." — BVH build and rendering, as Mitsuba's time is render only
    render_times+=("$(sed -E 's/.* spp in ([0-9.]+) s:.*/\1/' <<<"$line")")
    rmses+=("$($PY bench/compare_exr.py out/tessera_cbox.exr "$REF" --json | $PY -c 'import json,sys; print("%.5f" % json.load(sys.stdin)["rmse"])')")
  done
}
median() { printf '%s\n' "$@" | sort -n | awk '{a[NR]=$1} END {print (NR%2) ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2}'; }
tessera_runs
$PY bench/mitsuba_cbox.py --spp 256 --max-depth 8 --threads 2 --runs "$RUNS" --ref "$REF" -o out/mitsuba_cbox.exr
tessera_runs
echo "load after: $(cat /proc/loadavg)"
echo "tessera ${SPP} spp process wall times (s): ${times[*]}"
echo "tessera ${SPP} spp render times (s): ${render_times[*]}"
echo "tessera ${SPP} spp median: render $(median "${render_times[@]}") s; process $(median "${times[@]}") s (start-up, BVH build and EXR write included)"
echo "tessera ${SPP} spp RMSE per run (seeds 1..${RUNS}, twice): ${rmses[*]}; median $(median "${rmses[@]}")"
echo "tessera ${SPP} spp image vs reference:"
$PY bench/compare_exr.py out/tessera_cbox.exr "$REF"
