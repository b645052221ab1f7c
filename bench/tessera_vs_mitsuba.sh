#!/usr/bin/env bash
# Tessera against Mitsuba 3 on each SCENE, alternating in one run, medians of RUNS rounds, each
# one's time to reach the other's RMSE against a reference (bench/tessera_vs_mitsuba.py says how
# each figure is taken).
# Usage: bench/tessera_vs_mitsuba.sh SCENE...   (repository root; needs build/bin/tessera-worker)
# Per scene, known ones get their settings and reference:
#   scenes/cornell.json         256x256, depth 8, tests/data/reference/cbox/ref_depth8.exr (Mitsuba)
#   scenes/cornell-sphere.json  256x256, unbounded, out/ref/cornell-sphere_256x256.exr
#   scenes/hexroom.json         384x216, unbounded, out/ref/hexroom_384x216.exr, cross-checked
#                               against Tessera's 8192-spp 96x54 reference
#   anything else               its own film size, unbounded, out/ref/STEM.exr
# A missing reference is rendered with Mitsuba at REF_SPP first, and REF.exr.json records its
# spp (the reference's noise is subtracted on that basis). Environment: RUNS (3),
# TESSERA_SPP (64), MITSUBA_SPP (256), REF_SPP (4096), THREADS (2),
# PY (.venv-bench/bin/python, the venv of bench/README.md: a Python with Mitsuba 3.9 and drjit;
# llvm_ad_rgb needs libllvm19).
set -euo pipefail
[ $# -ge 1 ] || { sed -n 2,16p "$0"; exit 2; }
PY=${PY:-.venv-bench/bin/python}
command -v "$PY" >/dev/null ||
  { echo "no Python at PY=$PY: set PY to one with Mitsuba 3 (bench/README.md)" >&2; exit 2; }
RUNS=${RUNS:-3}
TESSERA_SPP=${TESSERA_SPP:-64}
MITSUBA_SPP=${MITSUBA_SPP:-256}
REF_SPP=${REF_SPP:-4096}
THREADS=${THREADS:-2}
echo "== $(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) cores,$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"
echo "tessera: $(git rev-parse --short HEAD 2>/dev/null || echo '?'), load before: $(cat /proc/loadavg)"
for scene in "$@"; do
  stem=$(basename "$scene" .json)
  case "$stem" in
    cornell) size=(--width 256 --height 256); depth=8; ref=tests/data/reference/cbox/ref_depth8.exr; ref_spp=(--reference-spp 8192) ;;
    cornell-sphere) size=(--width 256 --height 256); depth=-1; ref=out/ref/cornell-sphere_256x256.exr; ref_spp=() ;;
    hexroom) size=(--width 384 --height 216); depth=-1; ref=out/ref/hexroom_384x216.exr
      ref_spp=(--cross-check tests/data/reference/hexroom/ref_96x54_8192spp.exr) ;;
    *) size=(); depth=-1; ref=out/ref/$stem.exr; ref_spp=() ;;
  esac
  "$PY" bench/tessera_vs_mitsuba.py "$scene" --reference "$ref" "${size[@]}" --max-depth "$depth" \
    --tessera-spp "$TESSERA_SPP" --mitsuba-spp "$MITSUBA_SPP" --runs "$RUNS" --threads "$THREADS" \
    --ref-spp "$REF_SPP" "${ref_spp[@]}"
done
echo "load after: $(cat /proc/loadavg)"
