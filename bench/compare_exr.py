#!/usr/bin/env python3
"""Compare two linear RGB EXR images: RMSE, per-channel means, relative mean difference.

Usage: .venv-bench/bin/python bench/compare_exr.py TEST.exr REFERENCE.exr [--json]

RMSE is sqrt(mean((test - ref)^2)) over every pixel and the three channels (the figure
NOTES.md and tests/data/reference/README.md quote); per-channel RMSE is printed too.
"Relative mean difference" is (mean_test - mean_ref) / mean_ref per channel, in percent.
Images are read with Mitsuba's mi.Bitmap (the venv of bench/README.md); only the first three
channels (R, G, B) are compared. Both images must have the same size.
"""
import argparse
import json
import sys

import numpy as np


def read_rgb(path):
    """Reads an image as a float64 array H x W x 3 (linear RGB)."""
    import mitsuba as mi
    if mi.variant() is None:
        mi.set_variant("scalar_rgb")
    bmp = mi.Bitmap(str(path))
    if bmp.pixel_format() not in (mi.Bitmap.PixelFormat.RGB, mi.Bitmap.PixelFormat.RGBA):
        bmp = bmp.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, srgb_gamma=False)
    a = np.array(bmp, dtype=np.float64)
    if a.ndim == 2:
        a = a[:, :, None].repeat(3, axis=2)
    return a[:, :, :3]


def compare(test, ref):
    """Returns a dict of statistics comparing two H x W x 3 arrays."""
    if test.shape != ref.shape:
        raise ValueError(f"size differs: {test.shape} vs {ref.shape}")
    d = test - ref
    mt = test.reshape(-1, 3).mean(axis=0)
    mr = ref.reshape(-1, 3).mean(axis=0)
    return {
        "rmse": float(np.sqrt(np.mean(d * d))),
        "rmse_rgb": [float(x) for x in np.sqrt(np.mean((d * d).reshape(-1, 3), axis=0))],
        "mean_test": float(test.mean()),
        "mean_ref": float(ref.mean()),
        "mean_rgb_test": [float(x) for x in mt],
        "mean_rgb_ref": [float(x) for x in mr],
        "rel_mean_diff_rgb_percent": [float(x) for x in 100.0 * (mt - mr) / mr],
        "nonfinite_test": int(np.count_nonzero(~np.isfinite(test))),
    }


def format_stats(s):
    f = lambda v: " ".join(f"{x:.6f}" for x in v)
    p = lambda v: " ".join(f"{x:+.3f}%" for x in v)
    return (f"RMSE {s['rmse']:.6f}  (per channel {f(s['rmse_rgb'])})\n"
            f"mean test {s['mean_test']:.6f}  per channel {f(s['mean_rgb_test'])}\n"
            f"mean ref  {s['mean_ref']:.6f}  per channel {f(s['mean_rgb_ref'])}\n"
            f"relative mean difference per channel {p(s['rel_mean_diff_rgb_percent'])}"
            + (f"\nnon-finite values in test: {s['nonfinite_test']}" if s["nonfinite_test"] else ""))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("test")
    ap.add_argument("reference")
    ap.add_argument("--json", action="store_true", help="print the statistics as JSON")
    args = ap.parse_args()
    s = compare(read_rgb(args.test), read_rgb(args.reference))
    print(json.dumps(s, indent=1) if args.json else format_stats(s))
    return 0


if __name__ == "__main__":
    sys.exit(main())
