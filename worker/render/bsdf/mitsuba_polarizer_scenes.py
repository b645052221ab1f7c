#!/usr/bin/env python3
"""The mean colour of Mitsuba 3's and Tessera's renders of the public polarizer scenes, at a
small size, for docs/mitsuba_sweep.md's figures ("Feature scenes") (run by hand; CI runs no Mitsuba).

Mitsuba renders in llvm_ad_rgb (unpolarized: the polarizer passes half of the
light), the scene's own sensor re-made at --width x --height (120 x 90) (same to_world, x field of view and
filter); Tessera renders the same scene with --width/--height. The mean of each image leaves a
2-pixel border out (filters differ there). Prints, per scene, both means per
channel and their relative difference, and Mitsuba's standard error of the mean (over SEEDS
renders), so that a difference can be judged against noise.

Usage (PY: a Python with Mitsuba 3.9.1), from the repository root, with a built tessera-worker:
  $PY worker/render/bsdf/mitsuba_polarizer_scenes.py \
      --worker build/bin/tessera-worker SCENE.xml...
"""
import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np
import mitsuba as mi

mi.set_variant("llvm_ad_rgb")

WIDTH, HEIGHT, SPP, SEEDS = 120, 90, 64, 4


def small_sensor(sensor, width, height, spp):
    params = mi.traverse(sensor)
    film = sensor.film()
    aspect = film.size()[0] / film.size()[1]
    if abs(aspect - width / height) > 1e-6:
        sys.exit(f"the scene's film is {film.size()[0]} x {film.size()[1]}; pick a size of that aspect")
    return mi.load_dict({
        "type": "perspective",
        "fov": float(params["x_fov"][0]) if hasattr(params["x_fov"], "__getitem__") else float(params["x_fov"]),
        "fov_axis": "x",
        "near_clip": float(params["near_clip"]) if "near_clip" in params else 0.01,
        "far_clip": float(params["far_clip"]) if "far_clip" in params else 10000.0,
        "to_world": mi.ScalarTransform4f(np.array(params["to_world"].matrix)[..., 0]
                                         if np.array(params["to_world"].matrix).ndim == 3
                                         else np.array(params["to_world"].matrix)),
        "sampler": {"type": "independent", "sample_count": spp},
        "film": {"type": "hdrfilm", "width": width, "height": height,
                 "rfilter": film.rfilter()},
    })


def inner_mean(img):
    a = np.array(img)[2:-2, 2:-2, :3]
    return a.reshape(-1, 3).mean(axis=0)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--worker", required=True)
    ap.add_argument("--width", type=int, default=WIDTH)
    ap.add_argument("--height", type=int, default=HEIGHT)
    ap.add_argument("scenes", nargs="+")
    args = ap.parse_args()
    for path in args.scenes:
        scene = mi.load_file(path)
        sensor = small_sensor(scene.sensors()[0], args.width, args.height, SPP)
        means = np.array([inner_mean(mi.render(scene, sensor=sensor, spp=SPP, seed=s))
                          for s in range(SEEDS)])
        m_mean = means.mean(axis=0)
        m_err = means.std(axis=0, ddof=1) / np.sqrt(SEEDS)
        with tempfile.TemporaryDirectory() as tmp:
            out = os.path.join(tmp, "t.exr")
            subprocess.run([args.worker, "render", path, "-q", "--width", str(args.width),
                            "--height", str(args.height), "--spp", str(SPP * SEEDS), "-o", out], check=True)
            t_mean = inner_mean(mi.Bitmap(out))
        rel = (t_mean - m_mean) / m_mean
        print(f"{os.path.basename(path)}: Mitsuba {np.round(m_mean, 5)} +- {np.round(m_err, 5)}"
              f" ({SEEDS} x {SPP} spp), Tessera {np.round(t_mean, 5)} ({SEEDS * SPP} spp), "
              f"difference {np.round(100 * rel, 3)} %")


if __name__ == "__main__":
    main()
