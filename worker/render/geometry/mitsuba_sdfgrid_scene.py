#!/usr/bin/env python3
"""Mitsuba 3's image means of the SDF grid torus scenes (tests/data/mitsuba/sdfgrid/torus_smooth.xml
and torus_analytic.xml), read by sdf_grid_render_test.cpp (SdfGridRender.TorusScenesMatchMitsuba),
and optionally Tessera's beside them.

Mitsuba 3.9.1 (scalar_rgb) renders each scene as written (64 x 48, its gaussian filter, path
max_depth 8) with SEEDS seeds at SPP samples per pixel each. The mean of each image per channel
leaves a 2-pixel border out (Mitsuba truncates a splat's footprint there; docs/scenes.md);
printed are the mean over the seeds and its standard error (the spread of the seeds' means /
sqrt(SEEDS)).

With --worker, Tessera renders the same files (`tessera-worker render`, SEEDS seeds at SPP) and
the relative difference and its size in sigmas (both means' errors) are printed too, as
scripts/mitsuba_sweep.py judges them: ok within 4 sigma or 1 %.

Usage, from the repository root (PY: a Python with Mitsuba 3.9.1):
  $PY worker/render/geometry/mitsuba_sdfgrid_scene.py \
      > worker/render/geometry/mitsuba_sdfgrid_scene.txt
  $PY worker/render/geometry/mitsuba_sdfgrid_scene.py --worker build/bin/tessera-worker
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from mitsuba_scene_means import mitsuba_mean, report, tessera_mean  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
FOLDER = os.path.normpath(os.path.join(HERE, "../../../tests/data/mitsuba/sdfgrid"))
SCENES = ["torus_smooth", "torus_analytic"]
SPP, SEEDS, BORDER = 1024, 4, 2


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--worker", help="tessera-worker: render with Tessera too and compare")
    ap.add_argument("--spp", type=int, default=SPP)
    args = ap.parse_args()
    print(f"# Mitsuba 3.9.1 (scalar_rgb), tests/data/mitsuba/sdfgrid/*.xml at 64 x 48, {SEEDS} seeds x "
          f"{args.spp} spp, mean per channel without a {BORDER}-px border, written by "
          "mitsuba_sdfgrid_scene.py.")
    print("# Columns: scene channel mean standard_error")
    for name in SCENES:
        path = os.path.join(FOLDER, name + ".xml")
        m_mean, m_err = mitsuba_mean(path, args.spp, SEEDS, BORDER)
        for c, ch in enumerate("rgb"):
            print(f"{name} {ch} {m_mean[c]:.7g} {m_err[c]:.3g}", flush=True)
        if args.worker:
            report(name, tessera_mean(args.worker, path, args.spp, SEEDS, BORDER), (m_mean, m_err))


if __name__ == "__main__":
    main()
