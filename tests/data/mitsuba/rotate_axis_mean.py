#!/usr/bin/env python3
"""Mitsuba 3's image mean of rotate_axis.xml (a cube turned about the axis (0, 1, 1), not of unit
length), read by worker/render/integrators/mitsuba_scene_mean_test.cpp
(MitsubaSceneMean.RotateAboutANonUnitAxis), and optionally Tessera's beside it.

Mitsuba 3.9.1 (scalar_rgb) renders the scene as written (32 x 24, box filter, path max_depth 2)
with SEEDS seeds at SPP samples per pixel each; printed are the mean per channel over the seeds
and its standard error (the spread of the seeds' means / sqrt(SEEDS)). With the axis normalised
the mean is 23 % lower (0.0180 against 0.0235 in red at 64 spp).

With --worker, Tessera renders the same file (`tessera-worker render`, SEEDS seeds at SPP) and
the two are compared as scripts/mitsuba_sweep.py compares them: ok within 4 sigma or 1 %.

Usage, from the repository root (PY: a Python with Mitsuba 3.9.1):
  $PY tests/data/mitsuba/rotate_axis_mean.py > tests/data/mitsuba/rotate_axis_mean.txt
  $PY tests/data/mitsuba/rotate_axis_mean.py --worker build/bin/tessera-worker
"""
import argparse
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.normpath(os.path.join(HERE, "../../../worker/render")))
from mitsuba_scene_means import mitsuba_mean, report, tessera_mean  # noqa: E402

SCENE = os.path.join(HERE, "rotate_axis.xml")
SPP, SEEDS = 1024, 4


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--worker", help="tessera-worker: render with Tessera too and compare")
    ap.add_argument("--spp", type=int, default=SPP)
    args = ap.parse_args()
    m_mean, m_err = mitsuba_mean(SCENE, args.spp, SEEDS)
    print("# Mitsuba 3.9.1 (scalar_rgb), tests/data/mitsuba/rotate_axis.xml at 32 x 24, "
          f"{SEEDS} seeds x {args.spp} spp, mean per channel, written by rotate_axis_mean.py.")
    print("# Columns: channel mean standard_error")
    for c, name in enumerate("rgb"):
        print(f"{name} {m_mean[c]:.7g} {m_err[c]:.3g}")
    if args.worker:
        report("", tessera_mean(args.worker, SCENE, args.spp, SEEDS), (m_mean, m_err))


if __name__ == "__main__":
    main()
