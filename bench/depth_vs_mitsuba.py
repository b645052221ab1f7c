#!/usr/bin/env python3
"""Tessera's and Mitsuba 3's render time at each path depth, on one scene: where the cost per
sample parts.

tessera_vs_mitsuba.py compares whole renders. This one renders the same scene at max_depth 1
(camera rays and the emitters they see), 2 (one bounce: the direct light), 3, ... and unbounded,
with both renderers at the same spp and threads, alternating round by round, and prints each
depth's median times, their ratio and Tessera's rays per sample (closest-hit and shadow, from its
summary line). The time one more depth adds is what a vertex costs each renderer: the first
depths isolate the camera rays and the first diffuse vertex from the deep bounces.

Times as tessera_vs_mitsuba.py takes them: Tessera's is the render time its `rendered ... in T
s` line reports (Embree BVH build, the caustic guide's photon pass, rendering; no start-up or
image write); Mitsuba's is mi.render() plus reading the image back, after one untimed warm-up
render per depth that compiles the kernel. A depth's time includes Tessera's fixed cost (the
photon pass of a scene with glass or mirrors), so `--fixed` also renders 1 spp at max_depth 1
and prints that time.

Usage (repository root; PY is a Python with Mitsuba 3, e.g. .venv-bench/bin/python of
bench/README.md):
  $PY bench/depth_vs_mitsuba.py SCENE.json [--width W --height H]
      [--depths 1,2,3,-1] [--spp 64] [--runs 3] [--threads 2] [--tessera build/bin/tessera-worker]
      [--fixed]
"""
import argparse
import json
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.dont_write_bytecode = True  # no __pycache__ beside the scripts
sys.path.insert(0, str(Path(__file__).resolve().parent))
import tessera_to_mitsuba  # noqa: E402


def tessera(args, depth, spp, seed):
    """(seconds, closest-hit rays, shadow rays) from one `tessera-worker render` child."""
    with tempfile.TemporaryDirectory() as tmp:
        cmd = [args.tessera, "render", args.scene, "--spp", str(spp), "--max-depth", str(depth),
               "--threads", str(args.threads), "--seed", str(seed), "-q", "-o", str(Path(tmp) / "t.exr")]
        if args.width:
            cmd += ["--width", str(args.width), "--height", str(args.height)]
        proc = subprocess.run(cmd, capture_output=True, text=True)
    out = proc.stdout + proc.stderr
    if proc.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed ({proc.returncode}): {out.strip()}")
    m = re.search(r"^rendered \S+ in ([0-9.]+) s.*?\(([0-9]+) rays, ([0-9]+) shadow rays\)", out, re.M)
    if not m:
        raise SystemExit(f"no 'rendered ... in T s ... (N rays, M shadow rays)' line from {' '.join(cmd)}:\n{out}")
    return float(m.group(1)), int(m.group(2)), int(m.group(3))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene")
    ap.add_argument("--width", type=int)
    ap.add_argument("--height", type=int)
    ap.add_argument("--depths", default="1,2,3,-1", help="comma-separated max_depth values (Mitsuba's convention)")
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--tessera", default="build/bin/tessera-worker")
    ap.add_argument("--fixed", action="store_true", help="also time Tessera at 1 spp, max_depth 1")
    args = ap.parse_args()
    if (args.width is None) != (args.height is None):
        raise SystemExit("--width and --height go together")
    try:
        depths = [int(d) for d in args.depths.split(",")]
    except ValueError:
        raise SystemExit(f"--depths: not a comma-separated list of integers: {args.depths!r}")
    if any(d == 0 or d < -1 for d in depths):
        raise SystemExit(f"--depths: each depth is -1 (unbounded) or at least 1: {args.depths!r}")

    import drjit as dr
    import mitsuba as mi
    mi.set_variant("llvm_ad_rgb")
    dr.set_thread_count(args.threads)
    scene_json = json.loads(Path(args.scene).read_text())
    film = scene_json.get("film", {})
    width, height = args.width or film.get("width"), args.height or film.get("height")
    if not width or not height:
        raise SystemExit(f"{args.scene}: no film size in the scene: give --width and --height")
    with open("/proc/loadavg") as f:
        load_before = f.read().split()[:3]
    print(f"{args.scene}: {width}x{height}, {args.spp} spp, {args.threads} threads, "
          f"{args.runs} rounds alternating; load before {' '.join(load_before)}")
    if args.fixed:
        fixed = [tessera(args, 1, 1, r)[0] for r in range(args.runs)]
        print(f"Tessera at 1 spp, max_depth 1 (its fixed cost): median {statistics.median(fixed):.3f} s")
    for depth in depths:
        opts = argparse.Namespace(width=args.width, height=args.height, max_depth=depth, spp=args.spp, seed=0)
        with tempfile.TemporaryDirectory() as tmp:
            scene = mi.load_dict(tessera_to_mitsuba.convert(scene_json, Path(args.scene).parent, tmp, opts))
        np.array(mi.render(scene, spp=args.spp))  # compiles the kernel, untimed
        mitsuba_times, tessera_times = [], []
        for r in range(args.runs):
            t, rays, shadow = tessera(args, depth, args.spp, r)
            tessera_times.append(t)
            t0 = time.perf_counter()
            np.array(mi.render(scene, spp=args.spp, seed=r))
            mitsuba_times.append(time.perf_counter() - t0)
        samples = width * height * args.spp
        tt, mt = statistics.median(tessera_times), statistics.median(mitsuba_times)
        print(f"max_depth {depth:>2}: Tessera {tt:.3f} s (range {min(tessera_times):.3f}-{max(tessera_times):.3f}), "
              f"Mitsuba {mt:.3f} s ({min(mitsuba_times):.3f}-{max(mitsuba_times):.3f}), Tessera / Mitsuba {tt / mt:.2f}; "
              f"Tessera's rays per sample {rays / samples:.2f} closest-hit + {shadow / samples:.2f} shadow", flush=True)
    with open("/proc/loadavg") as f:
        print(f"load after {' '.join(f.read().split()[:3])}")


if __name__ == "__main__":
    main()
