#!/usr/bin/env python3
"""Mitsuba 3 peer benchmark on the reference Cornell box.

Renders tests/data/reference/cbox/mitsuba.xml (256x256, box filter, independent sampler, path
integrator) with a given spp / max_depth / thread count, times it, writes the EXR, and prints the
RMSE against a reference EXR and the per-channel means.

Usage (from the repository root, with the venv of bench/README.md):
  .venv-bench/bin/python bench/mitsuba_cbox.py --spp 256 --max-depth 8 --threads 2 --runs 5 \
      --ref tests/data/reference/cbox/ref_depth8.exr -o out/mitsuba_cbox_256.exr

Timing: each run is mi.render() plus the evaluation of the image (drjit is lazy: the kernel is
compiled and run when the image is read back), scene loading excluded. Run 1 includes JIT
compilation (or a load from Dr.Jit's on-disk kernel cache, ~/.drjit, when an earlier process
compiled the same kernel); it is reported apart, and the median is over runs 2..N. Every run
uses its own seed (seed, seed+1, ...); the EXR written is the last run's.
Threads: dr.set_thread_count(N) (N counts the Python thread itself; it is what `mitsuba -t N`
does).
"""
import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(Path(__file__).resolve().parent))
from compare_exr import compare, format_stats, read_rgb  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default=str(ROOT / "tests/data/reference/cbox/mitsuba.xml"))
    ap.add_argument("--variant", default="llvm_ad_rgb")
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--max-depth", type=int, default=8, help="Mitsuba convention; -1 = unbounded")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--runs", type=int, default=5, help="total runs; the first is the warm-up")
    ap.add_argument("--seed", type=int, default=0, help="seed of the first run")
    ap.add_argument("--ref", default=str(ROOT / "tests/data/reference/cbox/ref_depth8.exr"))
    ap.add_argument("-o", "--out", default=str(ROOT / "out/mitsuba_cbox.exr"))
    args = ap.parse_args()

    import drjit as dr
    import mitsuba as mi
    mi.set_variant(args.variant)
    mi.set_log_level(mi.LogLevel.Warn)
    dr.set_thread_count(args.threads)

    t0 = time.perf_counter()
    scene = mi.load_file(args.scene, spp=args.spp, max_depth=args.max_depth)
    t_load = time.perf_counter() - t0
    film = scene.sensors()[0].film()
    w, h = film.crop_size()
    ref = read_rgb(args.ref) if args.ref else None

    print(f"mitsuba {mi.__version__} drjit {dr.__version__} variant {args.variant}, "
          f"threads {dr.thread_count()}, {w}x{h}, spp {args.spp}, max_depth {args.max_depth}, "
          f"scene load {t_load:.3f} s")
    times, rmses = [], []
    img_np = None
    for i in range(args.runs):
        seed = args.seed + i
        t0 = time.perf_counter()
        img = mi.render(scene, spp=args.spp, seed=seed)
        img_np = np.array(img, dtype=np.float64)  # forces compilation/evaluation
        dt = time.perf_counter() - t0
        times.append(dt)
        line = f"run {i + 1} seed {seed}: {dt:.3f} s, {w * h * args.spp / dt / 1e6:.2f} M paths/s"
        if ref is not None:
            s = compare(img_np[:, :, :3], ref)
            rmses.append(s["rmse"])
            line += f", RMSE {s['rmse']:.5f}, mean {s['mean_test']:.6f}"
        print(line + (" (warm-up: JIT)" if i == 0 else ""), flush=True)

    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    mi.Bitmap(img_np[:, :, :3].astype(np.float32), pixel_format=mi.Bitmap.PixelFormat.RGB).write(args.out)
    print(f"wrote {args.out} (run {args.runs})")

    print(f"first run (incl. JIT): {times[0]:.3f} s")
    if len(times) > 1:
        med = statistics.median(times[1:])
        print(f"median of runs 2..{len(times)}: {med:.3f} s "
              f"(min {min(times[1:]):.3f}, max {max(times[1:]):.3f}), "
              f"{w * h * args.spp / med / 1e6:.2f} M paths/s")
    if ref is not None:
        print(f"RMSE vs {args.ref}: median {statistics.median(rmses):.5f} "
              f"(min {min(rmses):.5f}, max {max(rmses):.5f}) over {len(rmses)} runs")
        print("last run:\n" + format_stats(compare(img_np[:, :, :3], ref)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
