#!/usr/bin/env python3
"""Mitsuba 3's image mean of the hair strands scene (tests/data/mitsuba/hair/strands.xml), read by
hair_render_test.cpp (HairRender.StrandsSceneMatchesMitsuba), and optionally Tessera's beside it.

Mitsuba 3.9.1 (scalar_rgb) renders the scene as written (48 x 64, its gaussian filter, path
max_depth 16) with SEEDS seeds at SPP samples per pixel each. The mean of each image per
channel leaves a 2-pixel border out (Mitsuba truncates a splat's footprint there;
docs/scenes.md); printed are the mean over the seeds and its standard error (the spread of the
seeds' means / sqrt(SEEDS)).

With --worker, Tessera renders the same file (`tessera-worker render`, SEEDS seeds at SPP) and
the relative difference and its size in sigmas (both means' errors) are printed too, as
scripts/mitsuba_sweep.py judges them: ok within 4 sigma or 1 %.

Usage, from the repository root (PY: a Python with Mitsuba 3.9.1):
  $PY worker/render/bsdf/mitsuba_hair_scene.py \
      > worker/render/bsdf/mitsuba_hair_scene.txt
  $PY worker/render/bsdf/mitsuba_hair_scene.py --worker build/bin/tessera-worker
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from mitsuba_scene_means import mitsuba_mean, report, tessera_mean  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.normpath(os.path.join(HERE, "../../../tests/data/mitsuba/hair/strands.xml"))
SPP, SEEDS, BORDER = 1024, 4, 2


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--worker", help="tessera-worker: render with Tessera too and compare")
    ap.add_argument("--spp", type=int, default=SPP)
    args = ap.parse_args()
    m_mean, m_err = mitsuba_mean(SCENE, args.spp, SEEDS, BORDER)
    print("# Mitsuba 3.9.1 (scalar_rgb), tests/data/mitsuba/hair/strands.xml at 48 x 64, "
          f"{SEEDS} seeds x {args.spp} spp, mean per channel without a {BORDER}-px border, "
          "written by mitsuba_hair_scene.py.")
    print("# Columns: channel mean standard_error")
    for c, name in enumerate("rgb"):
        print(f"{name} {m_mean[c]:.7g} {m_err[c]:.3g}")
    if args.worker:
        report("", tessera_mean(args.worker, SCENE, args.spp, SEEDS, BORDER), (m_mean, m_err))


if __name__ == "__main__":
    main()
