#!/usr/bin/env python3
"""At equal time, is a denoised image closer to the truth than more samples? (docs/accuracy.md)

For each scene: `tessera-worker converge SCENE --reference REF --denoise --images DIR` renders
1, 2, 4, ... spp and measures RMSE of the raw and the denoised image at their own times (the
denoised one's time includes its guides and the denoising); this script adds HDR-FLIP (NVIDIA's
perceptual metric, pip `flip-evaluator`) of every level's two images, interpolates the raw
image's RMSE and FLIP at each denoised row's time (log-log, as converge does), and prints one
Markdown table per scene with the crossover: the first level from which plain Monte Carlo, given
the denoised image's time, is closer in that metric. With --crops X,Y,W,H it also cuts that
window of the reference, the raw and the denoised image at each of --crop-spp's levels as PNGs.

Usage (repository root; any Python with numpy and flip-evaluator):
  python3 bench/denoise_study.py --out out/denoise --spp 1024 --threads 2 \\
      cornell=scenes/cornell.json:tests/data/reference/cbox/ref_unbounded.exr [NAME=SCENE:REF ...]
"""
import argparse
import csv
import math
import os
import subprocess
import sys

import flip_evaluator as flip


def interpolate_at(times, values, t):
    """values at time t, log-log between the rows around it; None outside the rows' times."""
    for (t0, v0), (t1, v1) in zip(zip(times, values), zip(times[1:], values[1:])):
        if t0 <= t <= t1 and t0 > 0 and v0 > 0 and v1 > 0 and t1 > t0:
            f = math.log(t / t0) / math.log(t1 / t0)
            return math.exp(math.log(v0) + f * (math.log(v1) - math.log(v0)))
    return None


def flip_error(reference, test):
    _, mean, _ = flip.evaluate(reference, test, "HDR")
    return float(mean)


def run_scene(args, name, scene, reference):
    out = os.path.join(args.out, name)
    os.makedirs(out, exist_ok=True)
    table = os.path.join(out, "converge.csv")
    command = [args.worker, "converge", scene, "--reference", reference, "--spp", str(args.spp),
               "--denoise", "--images", out, "--csv", table, "--plot", os.path.join(out, "plot.png"),
               "--threads", str(args.threads), "-q"] + args.converge_arg
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
    with open(table) as f:
        rows = [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]
    for row in rows:
        spp = int(row["spp"])
        row["flip"] = flip_error(reference, os.path.join(out, f"raw-{spp}.exr"))
        row["denoised_flip"] = flip_error(reference, os.path.join(out, f"denoised-{spp}.exr"))
    return rows


def markdown(name, rows):
    times = [r["seconds"] for r in rows]
    lines = [f"#### {name}", "",
             "| spp | raw s | raw RMSE | raw FLIP | denoised s | denoised RMSE | denoised FLIP "
             "| raw RMSE, FLIP at the denoised time |",
             "|---:|---:|---:|---:|---:|---:|---:|---|"]
    crossover = {"RMSE": None, "FLIP": None}
    for r in rows:
        t = r["denoised_seconds"]
        raw_rmse = interpolate_at(times, [x["rmse"] for x in rows], t)
        raw_flip = interpolate_at(times, [x["flip"] for x in rows], t)
        at_time = "beyond the run" if raw_rmse is None else f"{raw_rmse:.5f}, {raw_flip:.4f}"
        lines.append(f"| {int(r['spp'])} | {r['seconds']:.3f} | {r['rmse']:.5f} | {r['flip']:.4f} "
                     f"| {t:.3f} | {r['denoised_rmse']:.5f} | {r['denoised_flip']:.4f} | {at_time} |")
        for metric, raw, denoised in (("RMSE", raw_rmse, r["denoised_rmse"]),
                                      ("FLIP", raw_flip, r["denoised_flip"])):
            if raw is not None and raw < denoised and crossover[metric] is None:
                crossover[metric] = int(r["spp"])
    lines.append("")
    for metric, spp in crossover.items():
        said = (f"from the {spp}-spp denoised image's time on" if spp is not None
                else "at no denoised level within the run")
        lines.append(f"Plain Monte Carlo is closer in {metric} {said}.")
    return "\n".join(lines) + "\n"


def crops(args, name, reference):
    x, y, w, h = (int(v) for v in args.crops.split(","))
    out = os.path.join(args.out, name)
    window = f"{w}x{h}+{x}+{y}"
    images = [("reference", reference)]
    for spp in (int(v) for v in args.crop_spp.split(",")):
        images += [(f"raw-{spp}", os.path.join(out, f"raw-{spp}.exr")),
                   (f"denoised-{spp}", os.path.join(out, f"denoised-{spp}.exr"))]
    for label, path in images:
        subprocess.run(["oiiotool", path, "--cut", window, "--resize", f"{w * 4}x{h * 4}:filter=box",
                        "--colorconvert", "linear", "sRGB", "-o",
                        os.path.join(out, f"crop-{label}.png")], check=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", nargs="+", help="NAME=SCENE:REFERENCE")
    parser.add_argument("--out", required=True, help="folder for the images, tables and plots")
    parser.add_argument("--worker", default="build/bin/tessera-worker")
    parser.add_argument("--spp", type=int, default=1024)
    parser.add_argument("--threads", type=int, default=0)
    parser.add_argument("--converge-arg", action="append", default=[],
                        help="passed on to converge, e.g. --converge-arg=--max-depth=8")
    parser.add_argument("--crops", help="X,Y,W,H: a window cut from each scene's images")
    parser.add_argument("--crop-spp", default="4,64", help="the levels cropped, e.g. 4,64")
    args = parser.parse_args()
    for item in args.scenes:
        name, _, files = item.partition("=")
        scene, _, reference = files.partition(":")
        if not name or not scene or not reference:
            sys.exit(f"{item}: expected NAME=SCENE:REFERENCE")
        rows = run_scene(args, name, scene, reference)
        text = markdown(name, rows)
        with open(os.path.join(args.out, name, "study.md"), "w") as f:
            f.write(text)
        print(text)
        if args.crops:
            crops(args, name, reference)


if __name__ == "__main__":
    main()
