#!/usr/bin/env python3
"""How much per-pixel sample allocation from a pilot pass could lower a scene's error, measured.

Spending a pixel's samples in proportion to its standard deviation s_i instead of evenly lowers
the image's mean squared error at the same total samples to (mean s_i)^2 / mean(s_i^2) of the
even allocation's: the oracle's figure, which needs the true s_i. A renderer only has an
estimate of s_i from a pilot pass, and a heavy-tailed pixel (a caustic, a lamp's reflection
seen through glass) shows its variance only once its rare bright path is found. This script
measures both:

- the truth: the per-pixel variance of one sample, from --truth-seeds renders at --truth-spp
  (sample variance across seeds, times spp, summed over the channels: what the RMSE counts);
- the pilot: P renders of 1 spp with other seeds stand for a pilot pass of P samples per pixel
  (each pixel's sample variance of luminance over them, as the noise rule's Sigma y, Sigma y^2
  give it), raw or smoothed by a 3x3 box, with a floor at a fraction of the mean s_i;
- the allocation of the remaining N - P samples per pixel in proportion to the estimated s_i,
  over the whole image or within each 64x64 tile (a tile's total kept), and the estimate
  w * pilot mean + (1 - w) * mean of the rest with the fixed weight w = P / N, which stays
  unbiased because the rest's count depends only on the pilot and w on nothing.

Each row prints the expected MSE at N samples per pixel on average, over the even allocation's
(below 1: the allocation helps). Nothing here depends on the machine's load.

Usage (repository root; PY is a Python with Mitsuba 3, e.g. .venv-bench/bin/python of
bench/README.md):
  $PY bench/allocation_from_pilot.py scenes/hexroom.json \\
      --width 384 --height 216 [--spp 64] [--truth-seeds 32] [--truth-spp 16] [--pilots 4,8,16]
"""
import argparse
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.dont_write_bytecode = True
sys.path.insert(0, str(Path(__file__).resolve().parent))
from compare_exr import read_rgb  # noqa: E402


def render(args, spp, seed, out):
    cmd = [args.worker, "render", args.scene, "--spp", str(spp), "--threads", str(args.threads),
           "--seed", str(seed), "-q", "-o", str(out)]
    if args.width:
        cmd += ["--width", str(args.width), "--height", str(args.height)]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed ({proc.returncode}): {proc.stderr.strip() or proc.stdout.strip()}")
    return read_rgb(out)


def luminance(img):
    return 0.2126 * img[..., 0] + 0.7152 * img[..., 1] + 0.0722 * img[..., 2]


def box3(a):
    """3x3 box filter, edges repeated."""
    p = np.pad(a, 1, mode="edge")
    h, w = a.shape
    return sum(p[dy:dy + h, dx:dx + w] for dy in range(3) for dx in range(3)) / 9.0


def allocate(s, budget, floor, tile):
    """Samples per pixel in proportion to s (floored at floor * the mean), averaging budget over
    the image (tile 0) or over each tile x tile block."""
    n = np.empty_like(s)
    h, w = s.shape
    step_y, step_x = (h, w) if tile == 0 else (tile, tile)
    for y in range(0, h, step_y):
        for x in range(0, w, step_x):
            b = s[y:y + step_y, x:x + step_x]
            m = b.mean()
            if not m > 0:
                n[y:y + step_y, x:x + step_x] = budget
                continue
            b = np.maximum(b, floor * m)
            n[y:y + step_y, x:x + step_x] = budget * b / b.mean()
    return n


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene")
    ap.add_argument("--worker", default="build/bin/tessera-worker")
    ap.add_argument("--width", type=int)
    ap.add_argument("--height", type=int)
    ap.add_argument("--spp", type=int, default=64, help="the average samples per pixel the allocation spends")
    ap.add_argument("--truth-seeds", type=int, default=32)
    ap.add_argument("--truth-spp", type=int, default=16)
    ap.add_argument("--pilots", default="4,8,16", help="pilot sizes P (samples per pixel) to try")
    ap.add_argument("--threads", type=int, default=2)
    args = ap.parse_args()
    pilots = [int(p) for p in args.pilots.split(",")]
    if any(p < 2 or p >= args.spp for p in pilots):
        raise SystemExit(f"--pilots: each must be in [2, {args.spp - 1}] (got {args.pilots})")
    with tempfile.TemporaryDirectory() as tmp:
        truth = np.stack([render(args, args.truth_spp, 1000 + s, Path(tmp) / f"t{s}.exr")
                          for s in range(args.truth_seeds)])
        pilot = np.stack([luminance(render(args, 1, 5000 + s, Path(tmp) / f"p{s}.exr"))
                          for s in range(max(pilots))])
    v = (truth.var(axis=0, ddof=1) * args.truth_spp).sum(axis=2)  # one sample's variance, per pixel
    n_even = float(args.spp)
    mse_even = float(v.mean()) / n_even
    print(f"{args.scene} {args.width or ''}x{args.height or ''}, {args.spp} spp on average; truth from "
          f"{args.truth_seeds} seeds x {args.truth_spp} spp")
    print(f"oracle (true s_i, no pilot): MSE x{(np.sqrt(v).mean() ** 2 / v.mean()):.3f} of the even allocation's")
    print("| pilot P | estimate | floor | scope | MSE / even allocation's |")
    print("|---|---|---|---|---|")
    for p in pilots:
        s2 = pilot[:p].var(axis=0, ddof=1)
        w = p / args.spp
        for name, est in (("raw", s2), ("3x3 box", box3(s2))):
            s = np.sqrt(np.maximum(est, 0.0))
            for floor in (0.1, 0.3):
                for scope, tile in (("image", 0), ("64 px tile", 64)):
                    n = allocate(s, args.spp - p, floor, tile)
                    mse = float((w * w * v / p + (1 - w) ** 2 * v / n).mean())
                    print(f"| {p} | {name} | {floor} | {scope} | {mse / mse_even:.3f} |")


if __name__ == "__main__":
    main()
