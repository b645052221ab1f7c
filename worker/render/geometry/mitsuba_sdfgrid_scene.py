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

Usage, from the repository root (Mitsuba 3.9.1):
  /work/venv-mitsuba/bin/python worker/render/geometry/mitsuba_sdfgrid_scene.py \
      > worker/render/geometry/mitsuba_sdfgrid_scene.txt
  /work/venv-mitsuba/bin/python worker/render/geometry/mitsuba_sdfgrid_scene.py --worker build/bin/tessera-worker
"""
import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np
import mitsuba as mi

mi.set_variant("scalar_rgb")

HERE = os.path.dirname(os.path.abspath(__file__))
FOLDER = os.path.normpath(os.path.join(HERE, "../../../tests/data/mitsuba/sdfgrid"))
SCENES = ["torus_smooth", "torus_analytic"]
SPP, SEEDS, BORDER = 1024, 4, 2


def inner_mean(image):
    a = np.array(image, dtype=np.float64)[BORDER:-BORDER, BORDER:-BORDER, :3]
    return a.reshape(-1, 3).mean(axis=0)


def mean_and_error(means):
    means = np.array(means)
    return means.mean(axis=0), means.std(axis=0, ddof=1) / np.sqrt(len(means))


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
        scene = mi.load_file(path, spp=args.spp)
        m_mean, m_err = mean_and_error([inner_mean(mi.render(scene, seed=s)) for s in range(SEEDS)])
        for c, ch in enumerate("rgb"):
            print(f"{name} {ch} {m_mean[c]:.7g} {m_err[c]:.3g}", flush=True)
        if not args.worker:
            continue
        t_means = []
        with tempfile.TemporaryDirectory() as tmp:
            for s in range(SEEDS):
                out = os.path.join(tmp, f"t{s}.exr")
                subprocess.run([args.worker, "render", path, "-q", "--spp", str(args.spp),
                                "--seed", str(s), "-o", out], check=True)
                t_means.append(inner_mean(mi.Bitmap(out)))
        t_mean, t_err = mean_and_error(t_means)
        rel = (t_mean - m_mean) / m_mean
        sigmas = np.abs(t_mean - m_mean) / np.sqrt(m_err ** 2 + t_err ** 2)
        for c, ch in enumerate("rgb"):
            verdict = "ok" if sigmas[c] <= 4 or abs(rel[c]) <= 0.01 else "MISMATCH"
            print(f"# {name} {ch}: Tessera {t_mean[c]:.6f} +- {t_err[c]:.2g}, Mitsuba {m_mean[c]:.6f} +- "
                  f"{m_err[c]:.2g}: {100 * rel[c]:+.3f} % ({sigmas[c]:.1f} sigma) {verdict}",
                  file=sys.stderr)


if __name__ == "__main__":
    main()
