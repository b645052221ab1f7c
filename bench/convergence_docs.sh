#!/usr/bin/env bash
# Regenerates docs/convergence/ (docs/accuracy.md): the Cornell box against Mitsuba's depth-8
# reference, and hexroom against its own reference (tests/data/reference/hexroom/), which
# `--reference-too` renders again first, cross-checked with Mitsuba 3.
# Usage: bench/convergence_docs.sh [--reference-too]   (repository root; build/bin/tessera-worker;
# the Mitsuba check needs the .venv-bench of bench/README.md, or PY=/path/to/python)
set -euo pipefail
PY=${PY:-.venv-bench/bin/python}
W=build/bin/tessera-worker
HEXREF=tests/data/reference/hexroom/ref_96x54_8192spp.exr
mkdir -p out docs/convergence
echo "== $(date -u '+%Y-%m-%d %H:%M UTC'), load $(cat /proc/loadavg)"
$W converge scenes/cornell.json --reference tests/data/reference/cbox/ref_depth8.exr --max-depth 8 \
  --spp 1024 --threads 2 -q --md docs/convergence/cornell.md --csv docs/convergence/cornell.csv \
  --plot docs/convergence/cornell.png
if [ "${1:-}" = "--reference-too" ]; then
  $W render scenes/hexroom.json --width 96 --height 54 --spp 8192 --seed 7777 --threads 1 -q -o "$HEXREF"
  for seed in 1 2; do
    $PY bench/tessera_to_mitsuba.py scenes/hexroom.json -o out/hex_mi_$seed.exr --width 96 --height 54 \
      --spp 8192 --seed $seed --threads 2
  done
  $PY bench/compare_exr.py "$HEXREF" out/hex_mi_1.exr
  $PY bench/compare_exr.py "$HEXREF" out/hex_mi_2.exr
  $PY bench/compare_exr.py out/hex_mi_1.exr out/hex_mi_2.exr
fi
$W converge scenes/hexroom.json --reference "$HEXREF" --spp 512 --threads 2 -q \
  --md out/hexroom_table.md --csv docs/convergence/hexroom.csv --plot docs/convergence/hexroom.png
echo "== done $(date -u '+%H:%M UTC'), load $(cat /proc/loadavg)"
