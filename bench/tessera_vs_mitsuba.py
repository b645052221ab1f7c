#!/usr/bin/env python3
"""Tessera against Mitsuba 3 on one scene: time for each to reach the other's RMSE.

Both renderers draw the same scene file (Mitsuba's copy made by tessera_to_mitsuba.py) at the
same size and depth on the same threads, alternating in one process: round r renders with
Tessera (a `tessera-worker render` child, seed r) and then with Mitsuba (in this process, seed r),
so load drifts hit both. Each image's RMSE is taken against REFERENCE (compare_exr.py).

Times: Tessera's is the render time its `rendered ... in T s` line reports (Embree BVH build
and rendering, no start-up or EXR write); Mitsuba's is mi.render() plus reading the image back,
after one untimed warm-up render that compiles the kernel (scene loading excluded).

Time to reach the other's RMSE, from the medians over the rounds: at a fixed cost per sample
and MSE proportional to 1/spp (independent samples; Tessera's low-discrepancy sampler converges
at least that fast, so the figure is, if anything, against Tessera), a renderer with RMSE e at
time t reaches RMSE e' at t (e / e')^2. The MSE against a reference includes the reference's own
noise, which pulls both ratios towards 1. With --reference-spp S (the reference is Mitsuba's
independent sampler at S spp, like the Mitsuba renders here at M spp) that noise is estimated as
Mitsuba's median MSE x M / (M + S) and the ratios are printed again with it subtracted.

Bias check: the mean of all of each renderer's rounds (R images with R seeds) is compared with
the reference too: its per-channel mean difference should be within noise and its RMSE about
the rounds' median over sqrt(R) when the renderer and reference agree.

--cross-check checks the reference against an independent image of the same view (for hexroom,
Tessera's own 96x54 reference of tests/data/reference/hexroom/), box-filtered down to its size.

When REFERENCE does not exist it is rendered first with Mitsuba at --ref-spp (seed 100000) and
written there, with REFERENCE.json saying how (its spp then serves as --reference-spp).

Usage (repository root; bench/tessera_vs_mitsuba.sh runs this for several scenes; PY is a
Python with Mitsuba 3, e.g. .venv-bench/bin/python of bench/README.md):
  $PY bench/tessera_vs_mitsuba.py SCENE.json --reference REF.exr
      [--width W --height H] [--max-depth D] [--tessera-spp N] [--mitsuba-spp 256] [--runs 3]
      [--threads 2] [--ref-spp 4096] [--tessera build/bin/tessera-worker]
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
from compare_exr import compare, read_rgb  # noqa: E402
import tessera_to_mitsuba  # noqa: E402


def load_mitsuba(scene_path, width, height, max_depth, spp):
    import mitsuba as mi
    opts = argparse.Namespace(width=width, height=height, max_depth=max_depth, spp=spp, seed=0)
    with tempfile.TemporaryDirectory() as tmp:
        d = tessera_to_mitsuba.convert(json.loads(Path(scene_path).read_text()), Path(scene_path).parent, tmp, opts)
        return mi.load_dict(d)


def mitsuba_render(scene, spp, seed):
    """(image H x W x 3 float64, seconds)."""
    import mitsuba as mi
    t0 = time.perf_counter()
    img = np.array(mi.render(scene, spp=spp, seed=seed), dtype=np.float64)  # evaluates the kernel
    return img[:, :, :3], time.perf_counter() - t0


def tessera_render(args, seed, out):
    """(image, seconds) from one `tessera-worker render` child."""
    cmd = [args.tessera, "render", args.scene, "--spp", str(args.tessera_spp), "--max-depth", str(args.max_depth),
           "--threads", str(args.threads), "--seed", str(seed), "-q", "-o", str(out)]
    if args.width:
        cmd += ["--width", str(args.width), "--height", str(args.height)]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed ({proc.returncode}): {proc.stderr.strip() or proc.stdout.strip()}")
    m = re.search(r"^rendered \S+ in ([0-9.]+) s", proc.stdout + proc.stderr, re.M)
    if not m:
        raise SystemExit(f"no 'rendered ... in T s' line from {' '.join(cmd)}:\n{proc.stdout}{proc.stderr}")
    return read_rgb(out), float(m.group(1))


def write_exr(path, img):
    import mitsuba as mi
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    mi.Bitmap(img.astype(np.float32), pixel_format=mi.Bitmap.PixelFormat.RGB).write(str(path))


def summary(name, images, ref, rmses):
    mean = compare(np.mean(images, axis=0), ref)
    rel = ", ".join(f"{x:+.2f} %" for x in mean["rel_mean_diff_rgb_percent"])
    return (f"{name}: mean of {len(images)} rounds vs reference: RMSE {mean['rmse']:.5f} "
            f"(rounds' median / sqrt({len(images)}) = {statistics.median(rmses) / len(images) ** 0.5:.5f}), "
            f"mean difference per channel {rel}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene")
    ap.add_argument("--reference", required=True, help="reference EXR (rendered with Mitsuba when missing)")
    ap.add_argument("--width", type=int)
    ap.add_argument("--height", type=int)
    ap.add_argument("--max-depth", type=int, default=-1, help="Mitsuba's convention; -1 = unbounded")
    ap.add_argument("--tessera-spp", type=int, default=64)
    ap.add_argument("--mitsuba-spp", type=int, default=256)
    ap.add_argument("--runs", type=int, default=3, help="rounds; 0 = only make the reference")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--ref-spp", type=int, default=4096, help="spp of a reference rendered here")
    ap.add_argument("--reference-spp", type=int,
                    help="spp of the reference when it is Mitsuba's (independent sampler): subtract its noise")
    ap.add_argument("--cross-check", help="an independent image of the same view (e.g. Tessera's own reference) "
                    "whose size divides the render's: the reference, box-filtered down to it, is compared with it")
    ap.add_argument("--tessera", default="build/bin/tessera-worker")
    ap.add_argument("--out", default="out/tessera_vs_mitsuba", help="folder for the renders")
    args = ap.parse_args()
    if (args.width is None) != (args.height is None):
        raise SystemExit("--width and --height go together")

    import drjit as dr
    import mitsuba as mi
    mi.set_variant("llvm_ad_rgb")
    mi.set_log_level(mi.LogLevel.Warn)
    dr.set_thread_count(args.threads)
    scene = load_mitsuba(args.scene, args.width, args.height, args.max_depth, args.mitsuba_spp)
    w, h = scene.sensors()[0].film().crop_size()
    print(f"== {args.scene} {w}x{h}, max depth {args.max_depth}, {args.threads} threads; Tessera "
          f"{args.tessera_spp} spp, Mitsuba {mi.__version__} llvm_ad_rgb {args.mitsuba_spp} spp; "
          f"{args.runs} rounds; load {Path('/proc/loadavg').read_text().split()[:3]}", flush=True)

    sidecar = Path(str(args.reference) + ".json")  # how a reference made here was made
    if not Path(args.reference).exists():
        img, dt = mitsuba_render(scene, args.ref_spp, 100000)
        write_exr(args.reference, img)
        sidecar.write_text(json.dumps({"renderer": f"mitsuba {mi.__version__} llvm_ad_rgb", "spp": args.ref_spp,
                                       "seed": 100000, "seconds": round(dt, 1)}) + "\n")
        print(f"reference: Mitsuba {args.ref_spp} spp, seed 100000, {dt:.1f} s -> {args.reference}", flush=True)
    if args.reference_spp is None and sidecar.exists():
        args.reference_spp = json.loads(sidecar.read_text())["spp"]
    ref = read_rgb(args.reference)
    if ref.shape[:2] != (h, w):
        raise SystemExit(f"{args.reference} is {ref.shape[1]}x{ref.shape[0]}, the renders {w}x{h}")

    if args.cross_check:
        other = read_rgb(args.cross_check)
        fy, fx = h // other.shape[0], w // other.shape[1]
        if fy * other.shape[0] != h or fx * other.shape[1] != w:
            raise SystemExit(f"{args.cross_check}: {other.shape[1]}x{other.shape[0]} does not divide {w}x{h}")
        down = ref.reshape(other.shape[0], fy, other.shape[1], fx, 3).mean(axis=(1, 3))
        c = compare(down, other)
        print(f"cross-check: reference box-filtered to {other.shape[1]}x{other.shape[0]} vs {args.cross_check}: "
              f"RMSE {c['rmse']:.5f}, mean difference per channel "
              + ", ".join(f"{x:+.2f} %" for x in c["rel_mean_diff_rgb_percent"]), flush=True)
    if args.runs == 0:
        return 0
    mitsuba_render(scene, args.mitsuba_spp, 99999)  # warm-up: JIT compilation, untimed
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    stem = Path(args.scene).stem
    t_times, t_rmses, t_images, m_times, m_rmses, m_images = [], [], [], [], [], []
    for r in range(1, args.runs + 1):
        img, dt = tessera_render(args, r, out / f"{stem}_tessera.exr")
        t_times.append(dt)
        t_rmses.append(compare(img, ref)["rmse"])
        t_images.append(img)
        img, dt = mitsuba_render(scene, args.mitsuba_spp, r)
        m_times.append(dt)
        m_rmses.append(compare(img, ref)["rmse"])
        m_images.append(img)
        print(f"round {r}: Tessera {t_times[-1]:.2f} s RMSE {t_rmses[-1]:.5f} | "
              f"Mitsuba {m_times[-1]:.2f} s RMSE {m_rmses[-1]:.5f} | load "
              f"{Path('/proc/loadavg').read_text().split()[0]}", flush=True)
    write_exr(out / f"{stem}_mitsuba.exr", m_images[-1])

    tt, te = statistics.median(t_times), statistics.median(t_rmses)
    mt, me = statistics.median(m_times), statistics.median(m_rmses)
    t_to_m = tt * (te / me) ** 2
    m_to_t = mt * (me / te) ** 2
    cost = (tt / args.tessera_spp) / (mt / args.mitsuba_spp)
    equal_spp = te * (args.tessera_spp / args.mitsuba_spp) ** 0.5 / me
    print(f"medians: Tessera {tt:.2f} s RMSE {te:.5f}; Mitsuba {mt:.2f} s RMSE {me:.5f}")
    print(f"Tessera reaches Mitsuba's RMSE {me:.5f} in {t_to_m:.2f} s = {t_to_m / mt:.2f}x Mitsuba's time")
    print(f"Mitsuba reaches Tessera's RMSE {te:.5f} in {m_to_t:.2f} s = {m_to_t / tt:.2f}x Tessera's time")
    print(f"per sample: Tessera's cost {cost:.2f}x Mitsuba's; RMSE at equal spp {equal_spp:.2f}x Mitsuba's")
    if args.reference_spp:
        ref_mse = me ** 2 * args.mitsuba_spp / (args.mitsuba_spp + args.reference_spp)
        tc, mc = (te ** 2 - ref_mse) ** 0.5, (me ** 2 - ref_mse) ** 0.5
        print(f"without the reference's noise (RMSE {ref_mse ** 0.5:.5f}, {args.reference_spp} spp): Tessera RMSE "
              f"{tc:.5f}, Mitsuba {mc:.5f}; Tessera reaches Mitsuba's in {tt * (tc / mc) ** 2 / mt:.2f}x "
              f"Mitsuba's time, Mitsuba Tessera's in {mt * (mc / tc) ** 2 / tt:.2f}x Tessera's; "
              f"RMSE at equal spp {tc * (args.tessera_spp / args.mitsuba_spp) ** 0.5 / mc:.2f}x Mitsuba's")
    print(summary("Tessera", t_images, ref, t_rmses))
    print(summary("Mitsuba", m_images, ref, m_rmses))
    return 0


if __name__ == "__main__":
    sys.exit(main())
