#!/usr/bin/env python3
"""Mitsuba 3's image mean of the volume texture scene (tests/data/mitsuba/volume/scene.xml), read
by volume_render_test.cpp (VolumeRender.SceneMatchesMitsuba), and optionally Tessera's beside it.

Mitsuba 3.9.1 (scalar_rgb) renders the scene as written (64 x 48, box filter, path max_depth 4)
with SEEDS seeds at SPP samples per pixel each; printed are the mean over the seeds of each
image's mean per channel and its standard error (the spread of the seeds' means / sqrt(SEEDS)).

With --worker, Tessera renders the same file (`tessera-worker render`, SEEDS seeds at SPP) and
the relative difference and its size in sigmas are printed too: ok within 4 sigma or 1 %.

With --write-grids, the scene's two grids are written first (they are committed; this is how
they were made): rgb.vol, 4 x 2 x 3 voxels of RGB, and grey.vol, 2 x 2 x 2 voxels of one
channel in a checker pattern.

Usage, from the repository root (PY: a Python with Mitsuba 3.9.1):
  $PY worker/render/texture/mitsuba_volume_scene.py \
      > worker/render/texture/mitsuba_volume_scene.txt
  $PY worker/render/texture/mitsuba_volume_scene.py --worker build/bin/tessera-worker
"""
import argparse
import os
import struct
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from mitsuba_scene_means import mitsuba_mean, report, tessera_mean  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
FOLDER = os.path.normpath(os.path.join(HERE, "../../../tests/data/mitsuba/volume"))
SCENE = os.path.join(FOLDER, "scene.xml")
SPP, SEEDS = 1024, 4


def write_grid(path, res, channels, values):
    """Mitsuba's .vol, version 3, float32, bounding box [0, 1]^3, x fastest."""
    nx, ny, nz = res
    assert len(values) == nx * ny * nz * channels
    with open(path, "wb") as f:
        f.write(b"VOL" + bytes([3]) + struct.pack("<i", 1) + struct.pack("<3i", nx, ny, nz))
        f.write(struct.pack("<i", channels) + struct.pack("<6f", 0, 0, 0, 1, 1, 1))
        f.write(np.asarray(values, dtype="<f4").tobytes())


def write_grids():
    rgb = []
    for z in range(3):
        for y in range(2):
            for x in range(4):
                rgb += [(x + 1) / 5, 0.2 + 0.6 * ((y + z) % 2), 0.9 - 0.3 * z]
    write_grid(os.path.join(FOLDER, "rgb.vol"), (4, 2, 3), 3, rgb)
    grey = [0.15 if (x + y + z) % 2 == 0 else 0.85
            for z in range(2) for y in range(2) for x in range(2)]
    write_grid(os.path.join(FOLDER, "grey.vol"), (2, 2, 2), 1, grey)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--worker", help="tessera-worker: render with Tessera too and compare")
    ap.add_argument("--spp", type=int, default=SPP)
    ap.add_argument("--write-grids", action="store_true", help="write rgb.vol and grey.vol first")
    args = ap.parse_args()
    if args.write_grids:
        write_grids()
    m_mean, m_err = mitsuba_mean(SCENE, args.spp, SEEDS)
    print("# Mitsuba 3.9.1 (scalar_rgb), tests/data/mitsuba/volume/scene.xml at 64 x 48, "
          f"{SEEDS} seeds x {args.spp} spp, image mean per channel, written by "
          "mitsuba_volume_scene.py.")
    print("# Columns: channel mean standard_error")
    for c, name in enumerate("rgb"):
        print(f"{name} {m_mean[c]:.7g} {m_err[c]:.3g}")
    if args.worker:
        report("", tessera_mean(args.worker, SCENE, args.spp, SEEDS), (m_mean, m_err))


if __name__ == "__main__":
    main()
