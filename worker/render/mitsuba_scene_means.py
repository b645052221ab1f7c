"""What the Mitsuba-mean scene scripts share (bsdf/mitsuba_hair_scene.py,
geometry/mitsuba_sdfgrid_scene.py, texture/mitsuba_volume_scene.py): render a scene file with
Mitsuba 3 (scalar_rgb) and, optionally, with `tessera-worker render`, SEEDS seeds each, take each
image's mean per channel (optionally without a border), and judge the two means as the C++ side
does (mitsuba_mean_test_support.h) and scripts/mitsuba_sweep.py: ok within 4 sigma or 1 %.

The scripts write the Mitsuba means the tests read; this module holds the one copy of how.
"""
import os
import subprocess
import sys
import tempfile

import numpy as np
import mitsuba as mi

mi.set_variant("scalar_rgb")


def image_mean(image, border=0):
    """The mean per channel (R, G, B) of an image, leaving `border` pixels out on every side."""
    a = np.array(image, dtype=np.float64)
    if border:
        a = a[border:-border, border:-border]
    return a[:, :, :3].reshape(-1, 3).mean(axis=0)


def mean_and_error(means):
    """The mean of per-seed means and its standard error (their spread / sqrt(seeds))."""
    means = np.array(means)
    return means.mean(axis=0), means.std(axis=0, ddof=1) / np.sqrt(len(means))


def mitsuba_mean(path, spp, seeds, border=0):
    """Mitsuba's image mean of the scene file at `path` and its standard error, over `seeds` seeds."""
    scene = mi.load_file(path, spp=spp)
    return mean_and_error([image_mean(mi.render(scene, seed=s), border) for s in range(seeds)])


def tessera_mean(worker, path, spp, seeds, border=0):
    """The same with Tessera (`WORKER render PATH --spp SPP --seed S`)."""
    means = []
    with tempfile.TemporaryDirectory() as tmp:
        for s in range(seeds):
            out = os.path.join(tmp, f"t{s}.exr")
            subprocess.run([worker, "render", path, "-q", "--spp", str(spp), "--seed", str(s), "-o", out],
                           check=True)
            means.append(image_mean(mi.Bitmap(out), border))
    return mean_and_error(means)


def report(label, tessera, mitsuba):
    """Prints to stderr, per channel, both means, their relative difference and its size in
    sigmas (both means' errors), and the verdict. `label` prefixes each line ("" for none)."""
    (t_mean, t_err), (m_mean, m_err) = tessera, mitsuba
    rel = (t_mean - m_mean) / m_mean
    sigmas = np.abs(t_mean - m_mean) / np.sqrt(m_err ** 2 + t_err ** 2)
    prefix = f"{label} " if label else ""
    for c, ch in enumerate("rgb"):
        verdict = "ok" if sigmas[c] <= 4 or abs(rel[c]) <= 0.01 else "MISMATCH"
        print(f"# {prefix}{ch}: Tessera {t_mean[c]:.6f} +- {t_err[c]:.2g}, Mitsuba {m_mean[c]:.6f} +- "
              f"{m_err[c]:.2g}: {100 * rel[c]:+.3f} % ({sigmas[c]:.1f} sigma) {verdict}",
              file=sys.stderr)
