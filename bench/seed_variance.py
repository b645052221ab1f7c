#!/usr/bin/env python3
"""Error at equal spp of one or more Tessera builds, free of machine load: the variance across seeds.

For an unbiased renderer the expected squared error of one image against the truth is its
variance, which K images of the same scene with K seeds estimate per pixel without any reference
(the sample variance across seeds, averaged over pixels and channels). Two builds (say, before
and after a change to sampling) are compared by that figure at the same spp: how many fewer
samples the new one needs for the same error is the ratio of their variances. Render times are
printed too, but they depend on the machine's load; the variance does not.

Builds are run alternating (seed 1 with each build, then seed 2, ...), so load drifts hit them
alike. With --reference, each build's mean image (all seeds) is also compared with it (box-
filtered down to the reference's size when that is smaller): a bias check, the channel means
should agree within noise.

With --maps DIR, writes for each build the per-pixel variance (luminance-weighted mean of the
channels) as DIR/SCENE_NAME_variance.exr, and prints where it lives: the share of the image's total
variance in its top 1 % and 10 % of pixels and in each cell of a 4 x 3 grid.

Usage (repository root; PY is a Python with Mitsuba 3, e.g. .venv-bench/bin/python of
bench/README.md):
  $PY bench/seed_variance.py SCENE.json --build old=OLD/build/bin/tessera-worker \\
      --build new=build/bin/tessera-worker [--width W --height H] [--max-depth D] [--spp 16]
      [--seeds 8] [--threads 2] [--reference REF.exr] [--maps out/maps]
"""
import argparse
import re
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.dont_write_bytecode = True
sys.path.insert(0, str(Path(__file__).resolve().parent))
from compare_exr import compare, read_rgb  # noqa: E402


def render(binary, args, seed, out):
    cmd = [binary, "render", args.scene, "--spp", str(args.spp), "--max-depth", str(args.max_depth),
           "--threads", str(args.threads), "--seed", str(seed), "-q", "-o", str(out)]
    if args.width:
        cmd += ["--width", str(args.width), "--height", str(args.height)]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed ({proc.returncode}): {proc.stderr.strip() or proc.stdout.strip()}")
    m = re.search(r"^rendered \S+ in ([0-9.]+) s", proc.stdout + proc.stderr, re.M)
    return read_rgb(out), float(m.group(1)) if m else float("nan")


def box_down(img, shape):
    h, w = shape[:2]
    fy, fx = img.shape[0] // h, img.shape[1] // w
    if fy * h != img.shape[0] or fx * w != img.shape[1]:
        raise SystemExit(f"cannot box-filter {img.shape[:2]} to {shape[:2]}")
    return img.reshape(h, fy, w, fx, 3).mean(axis=(1, 3))


def where_it_lives(var_map):
    total = var_map.sum()
    flat = np.sort(var_map.ravel())[::-1]
    top1 = flat[: max(1, len(flat) // 100)].sum() / total
    top10 = flat[: max(1, len(flat) // 10)].sum() / total
    h, w = var_map.shape
    rows = []
    for gy in range(3):
        cells = []
        for gx in range(4):
            cell = var_map[gy * h // 3:(gy + 1) * h // 3, gx * w // 4:(gx + 1) * w // 4]
            cells.append(f"{100 * cell.sum() / total:5.1f}")
        rows.append(" ".join(cells))
    return top1, top10, rows


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene")
    ap.add_argument("--build", action="append", required=True, help="NAME=path/to/tessera-worker")
    ap.add_argument("--width", type=int)
    ap.add_argument("--height", type=int)
    ap.add_argument("--max-depth", type=int, default=-1)
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--seeds", type=int, default=8)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--reference")
    ap.add_argument("--maps")
    args = ap.parse_args()
    builds = [b.split("=", 1) for b in args.build]
    images = {name: [] for name, _ in builds}
    times = {name: [] for name, _ in builds}
    with tempfile.TemporaryDirectory() as tmp:
        for seed in range(1, args.seeds + 1):
            for name, binary in builds:
                img, t = render(binary, args, seed, Path(tmp) / f"{name}_{seed}.exr")
                images[name].append(img)
                times[name].append(t)
    ref = read_rgb(args.reference) if args.reference else None
    base = None
    # The first build's 1 % noisiest pixels (often edges of directly seen lights, which no light
    # sampling touches): the variance without them is printed too.
    first = np.stack(images[builds[0][0]]).var(axis=0, ddof=1).mean(axis=2)
    calm = first <= np.quantile(first, 0.99)
    base_calm = None
    # That selection favours the first build: it drops the pixels where the first build's own
    # seeds happened to be noisy, and keeps the other builds' unlucky ones. Symmetric too: the
    # pixels outside every build's noisiest 1 %, and the median over pixels of the ratio.
    per_build = {name: np.stack(images[name]).var(axis=0, ddof=1).mean(axis=2) for name, _ in builds}
    calm_all = np.logical_and.reduce([v <= np.quantile(v, 0.99) for v in per_build.values()])
    print(f"{args.scene} {args.width or ''}x{args.height or ''} depth {args.max_depth}, {args.spp} spp, "
          f"{args.seeds} seeds, {args.threads} threads")
    for name, _ in builds:
        stack = np.stack(images[name])
        var = stack.var(axis=0, ddof=1)  # per pixel and channel
        mse = float(var.mean())
        base = base or mse
        mse_calm = float(var.mean(axis=2)[calm].mean())
        base_calm = base_calm or mse_calm
        line = (f"{name}: variance of one image (mean over pixels and channels) {mse:.6g}, RMSE {mse ** 0.5:.5f}, "
                f"x{mse / base:.3f} of the first build's variance; render time median "
                f"{float(np.median(times[name])):.2f} s (range {min(times[name]):.2f}-{max(times[name]):.2f})")
        print(line)
        print(f"  without the first build's noisiest 1 % of pixels: variance {mse_calm:.6g}, "
              f"x{mse_calm / base_calm:.3f} of the first build's")
        v, v0 = per_build[name], per_build[builds[0][0]]
        both = (v > 0) & (v0 > 0)
        print(f"  without every build's noisiest 1 % of pixels: x{v[calm_all].mean() / v0[calm_all].mean():.3f} "
              f"of the first build's; median over pixels of the variance ratio x{float(np.median(v[both] / v0[both])):.3f}")
        if ref is not None:
            mean_img = stack.mean(axis=0)
            if mean_img.shape != ref.shape:
                mean_img = box_down(mean_img, ref.shape)
            c = compare(mean_img, ref)
            per_image = [compare(box_down(i, ref.shape) if i.shape != ref.shape else i, ref)["rmse"] for i in images[name]]
            rel = ", ".join(f"{x:+.2f} %" for x in c["rel_mean_diff_rgb_percent"])
            print(f"  against {args.reference}: median RMSE of one image {float(np.median(per_image)):.5f}; "
                  f"mean of {args.seeds} images: RMSE {c['rmse']:.5f}, channel means {rel}")
        lum = 0.2126 * var[:, :, 0] + 0.7152 * var[:, :, 1] + 0.0722 * var[:, :, 2]
        top1, top10, rows = where_it_lives(lum)
        print(f"  variance share: top 1 % of pixels {100 * top1:.1f} %, top 10 % {100 * top10:.1f} %; "
              f"4 x 3 grid (% per cell, top row first): {' | '.join(rows)}")
        if args.maps:
            import mitsuba as mi
            Path(args.maps).mkdir(parents=True, exist_ok=True)
            path = Path(args.maps) / f"{Path(args.scene).stem}_{name}_variance.exr"
            mi.Bitmap(np.repeat(lum[:, :, None], 3, axis=2).astype(np.float32),
                      pixel_format=mi.Bitmap.PixelFormat.RGB).write(str(path))
            print(f"  wrote {path}")


if __name__ == "__main__":
    main()
