#!/usr/bin/env python3
"""Every Mitsuba 3 scene Tessera accepts, rendered by both, compared by image mean (docs/mitsuba_sweep.md).

For each scene under FOLDER... that `tessera-worker convert` accepts (the rule of
scripts/mitsuba_coverage.py, which this script imports), renders at a small size:
  - with Mitsuba 3 (PYTHON given by --mitsuba, variant scalar_rgb): the scene as loaded, its
    film resized through mi.traverse (`film.size`, `film.crop_size`, `film.crop_offset`) to
    --width and the height that keeps the film's aspect ratio, the scene's own pixel filter,
    sensor and integrator (Mitsuba's default `path` where the scene has none, which mi.render
    would refuse: Tessera renders that too), `mi.render(scene, seed=S, spp=N)`;
  - with `tessera-worker render SCENE --width W --height H --spp N --seed S -D spp=N`;
  each with two seeds. Compared: per-channel image means with a 2-pixel border left out (Mitsuba
  truncates a splat's footprint there), the noise of each mean estimated from the per-pixel
  difference of the two seeds (sigma^2 = mean((a - b)^2) / (2 * pixels) for the mean of one
  render, halved for the mean of both), NaN/Inf pixels, and each render's wall time.

The table, sorted by |difference| / noise (the worst channel), has one row per scene:
  scene, Mitsuba mean (r g b), Tessera mean, relative difference, sigmas, NaN/Inf, times, verdict.
Verdict: `ok` within 4 sigma or 1 %; `MISMATCH` beyond 4 sigma and 1 %; `nan` if either image
has a NaN or Inf pixel; `skipped` with the reason when Mitsuba fails or takes more than
--mitsuba-limit CPU seconds (default 60) for one render.

Renders are cached under --cache (default build/mitsuba_sweep/) by scene path, size, spp and
seed, so a second run only renders what is new (delete the folder to start over). Every render
runs niced (--nice, default 10). Times are CPU seconds (user + system) of the render:
for Mitsuba of mi.render alone, for Tessera of the whole `tessera-worker render` process.

Usage (PY: a Python with Mitsuba 3 and numpy, e.g. the .venv-bench of bench/README.md):
  $PY scripts/mitsuba_sweep.py --mitsuba $PY \
      [--worker build/bin/tessera-worker] [--width 96] [--spp 64] [--jobs 1] \
      [--only SUBSTRING ...] [--markdown OUT.md] FOLDER...
The script itself runs under any Python 3 with numpy and OpenEXR reading through Mitsuba:
run it with the same PYTHON (it reads the EXRs with mi.Bitmap).
"""

import argparse
import concurrent.futures
import hashlib
import json
import os
import re
import subprocess
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mitsuba_coverage  # noqa: E402  (find_scenes, convert)

BORDER = 2
SIGMA_BAR = 4.0
RELATIVE_BAR = 0.01

# Run as `PYTHON -c MITSUBA_RENDER scene out.exr width spp seed [name=value ...]` (scalar_rgb):
# renders the scene at `width` x the height that keeps the film's aspect, writes the EXR and
# prints one JSON line {"height", "seconds", "filter"}.
MITSUBA_RENDER = r"""
import json, sys, time
import mitsuba as mi
mi.set_variant('scalar_rgb')
scene_path, out, width, spp, seed = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5])
defines = dict(d.split('=', 1) for d in sys.argv[6:])
scene = mi.load_file(scene_path, **defines)
sensor = scene.sensors()[0]
film = sensor.film()
w0, h0 = film.size()
height = max(1, int(round(width * h0 / w0)))
params = mi.traverse(sensor)
params['film.size'] = mi.ScalarVector2u(width, height)
params['film.crop_size'] = mi.ScalarVector2u(width, height)
params['film.crop_offset'] = mi.ScalarPoint2u(0, 0)
params.update()
# A scene without an <integrator>: Mitsuba's documented default, `path` (what Tessera renders);
# mi.render refuses such a scene otherwise.
extra = {}
if scene.integrator() is None:
    extra['integrator'] = mi.load_dict({'type': 'path'})
t0 = time.process_time()
image = mi.render(scene, sensor=sensor, seed=seed, spp=spp, **extra)
seconds = time.process_time() - t0
import numpy as np
a = np.array(image, dtype=np.float32)
if a.ndim == 2:
    a = a[:, :, None]
if a.shape[2] == 1:
    a = np.repeat(a, 3, axis=2)
mi.Bitmap(np.ascontiguousarray(a[:, :, :3])).write(out)
print(json.dumps({"height": height, "seconds": seconds, "filter": str(film.rfilter()).split('[')[0].strip(),
                  "original": [int(w0), int(h0)], "default_integrator": bool(extra)}))
"""


def cache_path(cache, scene, tag):
    digest = hashlib.sha1(os.path.abspath(scene).encode()).hexdigest()[:10]
    name = os.path.splitext(os.path.basename(scene))[0]
    return os.path.join(cache, f"{name}-{digest}-{tag}")


def uses_spp(scene):
    """Whether the scene or a file it includes names `$spp` (a shallow look: includes are
    looked up beside the including file)."""
    seen, todo = set(), [os.path.abspath(scene)]
    while todo:
        path = todo.pop()
        if path in seen or not os.path.exists(path):
            continue
        seen.add(path)
        with open(path, errors="replace") as f:
            text = f.read()
        if "$spp" in text:
            return True
        for name in re.findall(r'<include[^>]*filename="([^"]+)"', text):
            todo.append(os.path.join(os.path.dirname(path), name))
    return False


def render_mitsuba(args, scene, seed):
    """(image path, info dict) or (None, reason); cached."""
    base = cache_path(args.cache, scene, f"mi-w{args.width}-s{args.spp}-seed{seed}")
    exr, info_file = base + ".exr", base + ".json"
    if os.path.exists(info_file):
        with open(info_file) as f:
            info = json.load(f)
        return (exr if "error" not in info else None), info
    # `$spp` as Tessera gets it (`-D spp=N`); Mitsuba refuses a parameter the scene never uses.
    defines = [*args.defines] + ([f"spp={args.spp}"] if uses_spp(scene) else [])
    command = ["nice", "-n", str(args.nice), args.mitsuba, "-c", MITSUBA_RENDER, scene, exr,
               str(args.width), str(args.spp), str(seed), *defines]
    t0 = time.time()
    try:
        result = subprocess.run(command, capture_output=True, text=True,
                                timeout=args.mitsuba_wall_limit)
        # Mitsuba's log may put a colour escape before the line.
        results = [l[l.index('{"height"'):] for l in result.stdout.splitlines()
                   if '{"height"' in l]
        if result.returncode != 0 or not results:
            lines = [l for l in (result.stderr + result.stdout).splitlines() if l.strip()]
            info = {"error": "Mitsuba failed: " + (lines[-1] if lines else "(no message)")[:200]}
        else:
            info = json.loads(results[-1])
            if info["seconds"] > args.mitsuba_limit:
                info = {"error": f"Mitsuba took {info['seconds']:.0f} s of CPU > {args.mitsuba_limit:.0f} s"}
    except subprocess.TimeoutExpired:
        info = {"error": f"Mitsuba took more than {time.time() - t0:.0f} s"}
    with open(info_file, "w") as f:
        json.dump(info, f)
    return (exr if "error" not in info else None), info


def render_tessera(args, scene, height, seed):
    base = cache_path(args.cache, scene, f"ts-w{args.width}-h{height}-s{args.spp}-seed{seed}")
    exr, info_file = base + ".exr", base + ".json"
    if os.path.exists(info_file):
        with open(info_file) as f:
            info = json.load(f)
        return (exr if "error" not in info else None), info
    command = ["nice", "-n", str(args.nice), args.worker, "render", scene, "-o", exr, "-q",
               "--width", str(args.width), "--height", str(height), "--spp", str(args.spp),
               "--seed", str(seed), "--threads", str(args.threads), "-D", f"spp={args.spp}"]
    for define in args.defines:
        command += ["-D", define]
    with tempfile.TemporaryFile("w+") as stderr:
        process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=stderr, text=True)
        _, status, usage = os.wait4(process.pid, 0)
        process.returncode = os.waitstatus_to_exitcode(status)
        stderr.seek(0)
        message = stderr.read()
    seconds = usage.ru_utime + usage.ru_stime
    if process.returncode != 0:
        info = {"error": "Tessera failed: " + mitsuba_coverage.first_reason(message)[:200]}
    else:
        info = {"seconds": seconds}
    with open(info_file, "w") as f:
        json.dump(info, f)
    return (exr if "error" not in info else None), info


def read_exr(path):
    import mitsuba as mi  # its variant is set once in main(), before any thread
    a = np.array(mi.Bitmap(path), dtype=np.float64)
    if a.ndim == 2:
        a = a[:, :, None]
    if a.shape[2] == 1:
        a = np.repeat(a, 3, axis=2)
    return a[:, :, :3]


def statistics(images):
    """Mean per channel of the images' average (border left out), its sigma, non-finite count."""
    inner = [i[BORDER:-BORDER, BORDER:-BORDER] for i in images]
    bad = sum(int((~np.isfinite(i)).any(axis=2).sum()) for i in inner)
    finite = [np.where(np.isfinite(i), i, 0.0) for i in inner]
    pixels = finite[0].shape[0] * finite[0].shape[1]
    mean = np.mean([f.mean(axis=(0, 1)) for f in finite], axis=0)
    # Var of one render's mean = E[(a-b)^2] / 2 / pixels; the mean of two renders halves it.
    var_one = np.mean((finite[0] - finite[1]) ** 2, axis=(0, 1)) / 2.0 / pixels
    return mean, np.sqrt(var_one / 2.0), bad


def compare(args, scene):
    row = {"scene": os.path.relpath(scene, args.relative_to) if args.relative_to else scene}
    mi_images, mi_seconds = [], []
    for seed in (0, 1):
        exr, info = render_mitsuba(args, scene, seed)
        if exr is None:
            row["verdict"] = "skipped: " + info["error"]
            return row
        mi_images.append(exr)
        mi_seconds.append(info["seconds"])
        height = info["height"]
        row["filter"] = info.get("filter", "")
    ts_images, ts_seconds = [], []
    for seed in (0, 1):
        exr, info = render_tessera(args, scene, height, seed)
        if exr is None:
            row["verdict"] = "skipped: " + info["error"]
            return row
        ts_images.append(exr)
        ts_seconds.append(info["seconds"])
    m_mean, m_sigma, m_bad = statistics([read_exr(p) for p in mi_images])
    t_mean, t_sigma, t_bad = statistics([read_exr(p) for p in ts_images])
    sigma = np.sqrt(m_sigma ** 2 + t_sigma ** 2)
    diff = t_mean - m_mean
    sigmas = np.abs(diff) / np.maximum(sigma, 1e-12)
    relative = np.abs(diff) / np.maximum(np.abs(m_mean), 1e-6)
    worst = int(np.argmax(sigmas))
    row.update({
        "size": f"{args.width}x{height}", "mitsuba": m_mean.tolist(), "tessera": t_mean.tolist(),
        "relative": float(relative[worst]) * np.sign(diff[worst]),
        "sigmas": float(sigmas[worst]), "nonfinite": [m_bad, t_bad],
        "mitsuba_s": sum(mi_seconds), "tessera_s": sum(ts_seconds),
    })
    if m_bad or t_bad:
        row["verdict"] = "nan"
    elif sigmas[worst] > SIGMA_BAR and np.max(relative * (sigmas > SIGMA_BAR)) > RELATIVE_BAR:
        row["verdict"] = "MISMATCH"
    else:
        row["verdict"] = "ok"
    return row


def safe_compare(args, scene):
    try:
        return compare(args, scene)
    except Exception as error:  # one broken scene must not stop the sweep
        return {"scene": os.path.relpath(scene, args.relative_to) if args.relative_to else scene,
                "verdict": f"skipped: {type(error).__name__}: {error}"[:200]}


def rgb(v):
    return " ".join(f"{x:.4g}" for x in v)


def table(rows):
    done = sorted((r for r in rows if "sigmas" in r), key=lambda r: -r["sigmas"])
    skipped = [r for r in rows if "sigmas" not in r]
    lines = ["| scene | size | filter | Mitsuba mean (r g b) | Tessera mean (r g b) | diff | sigmas "
             "| NaN/Inf (mi, ts) | Mitsuba s | Tessera s | verdict |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in done:
        lines.append(f"| {r['scene']} | {r['size']} | {r['filter']} | {rgb(r['mitsuba'])} | "
                     f"{rgb(r['tessera'])} | {100 * r['relative']:+.2f} % | {r['sigmas']:.1f} | "
                     f"{r['nonfinite'][0]}, {r['nonfinite'][1]} | {r['mitsuba_s']:.1f} | "
                     f"{r['tessera_s']:.1f} | {r['verdict']} |")
    for r in skipped:
        lines.append(f"| {r['scene']} | | | | | | | | | | {r['verdict']} |")
    counts = {}
    for r in rows:
        key = r["verdict"].split(":")[0]
        counts[key] = counts.get(key, 0) + 1
    lines.append("")
    lines.append("verdicts: " + ", ".join(f"{k} {v}" for k, v in sorted(counts.items())))
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folders", nargs="+", metavar="FOLDER")
    parser.add_argument("--mitsuba", required=True, metavar="PYTHON",
                        help="a Python with mitsuba 3.9 installed")
    parser.add_argument("--worker", default="build/bin/tessera-worker")
    parser.add_argument("--width", type=int, default=96)
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--threads", type=int, default=1, help="tessera-worker's --threads")
    parser.add_argument("--jobs", type=int, default=1, help="scenes at a time")
    parser.add_argument("--mitsuba-limit", type=float, default=60.0,
                        help="skip a scene whose Mitsuba render takes more CPU seconds")
    parser.add_argument("--mitsuba-wall-limit", type=float, default=600.0,
                        help="skip a scene whose Mitsuba load and render take longer (wall seconds)")
    parser.add_argument("--nice", type=int, default=10, help="niceness of every render")
    parser.add_argument("--accepted", metavar="FILE",
                        help="scripts/mitsuba_coverage.py's output: sweep its `accepted` lines "
                             "instead of converting every scene again")
    parser.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE")
    parser.add_argument("--only", action="append", default=[], metavar="SUBSTRING",
                        help="only scenes whose path contains this (repeatable)")
    parser.add_argument("--cache", default="build/mitsuba_sweep")
    parser.add_argument("--relative-to", help="print scene paths relative to this folder")
    parser.add_argument("--markdown", help="also write the table to this file")
    args = parser.parse_args()
    os.makedirs(args.cache, exist_ok=True)
    import mitsuba as mi  # to read EXRs (read_exr); setting a variant is not thread-safe
    mi.set_variant("scalar_rgb")

    if args.accepted:
        with open(args.accepted) as f:
            # A scene's line is "accepted  PATH[ [N stand-ins: ...]]" (two spaces; the summary
            # line has one); the path is the rest of the line, spaces and all.
            scenes = [re.sub(r"\s+\[\d+ stand-ins?:.*\]$", "", l[len("accepted  "):].rstrip("\n"))
                      for l in f if l.startswith("accepted  ")]
        scenes = [s for s in scenes if any(os.path.abspath(s).startswith(os.path.abspath(d))
                                           for d in args.folders)]
    else:
        scenes = mitsuba_coverage.find_scenes(args.folders)
    if args.only:
        scenes = [s for s in scenes if any(o in s for o in args.only)]
    if args.accepted:
        accepted = scenes
    else:
        defines = [f"spp={args.spp}", *args.defines]
        with concurrent.futures.ThreadPoolExecutor(max(1, args.jobs)) as pool:
            reasons = list(pool.map(
                lambda s: mitsuba_coverage.convert(args.worker, None, defines, s), scenes))
        accepted = [s for s, r in zip(scenes, reasons) if r is None]
    print(f"{len(accepted)} of {len(scenes)} scenes accepted by Tessera", file=sys.stderr)

    rows = []
    with concurrent.futures.ThreadPoolExecutor(max(1, args.jobs)) as pool:
        for row in pool.map(lambda s: safe_compare(args, s), accepted):
            extra = f" {row['sigmas']:.1f} sigma" if "sigmas" in row else ""
            print(f"{row['verdict']:>9}{extra}  {row['scene']}", file=sys.stderr, flush=True)
            rows.append(row)
    text = table(rows)
    print(text)
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write(text + "\n")


if __name__ == "__main__":
    main()
