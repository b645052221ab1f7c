#!/usr/bin/env python3
"""Mitsuba 3 references for the published-scene acceptance test (tests/render/mitsuba_scenes_test.cpp).

For each scene of SCENES (files copied unchanged from mitsuba-renderer/mitsuba-data, see
README.md here), renders with Mitsuba 3 (llvm_ad_rgb) through a sensor made from the scene's own
camera (same to_world, field of view and pixel filter) at the test's small size:
  - the test spp: the first of SPP_CHOICES at which seeds 0 and 1 agree in image mean within
    0.2 % per channel (below it a mean cannot be judged to 0.5 %);
  - the reference at REF_FACTOR = 32 x the test spp (seed 1000), written to references/<scene>.exr;
  - four renders at the test spp (seeds 0-3): the median of their RMSEs against the reference is
    the bar Tessera must meet (times 1.25 in the test);
  - for a film with a tent or gaussian filter, the same two ways with a box filter: the ratio of
    box to filtered RMSE is the noise Mitsuba's splatting removes that filter importance sampling
    keeps (docs/renderer.md), by which the test's bar grows.
A 2-pixel border is left out of every comparison (Mitsuba truncates a splat's footprint there).
Writes references/references.json, read by the test.

  /path/to/venv/bin/python tests/data/mitsuba/make_references.py     # venv with mitsuba==3.9.*
"""
import json
import os
import statistics
import sys
import time

import mitsuba as mi
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SCENES_DIR = os.path.join(HERE, "docs", "scenes")
OUT = os.path.join(HERE, "references")
WIDTH, HEIGHT = 64, 48
SPP_CHOICES = (64, 128, 256, 512, 1024, 2048)
REF_FACTOR = 32
BORDER = 2

# Scenes whose test spp starts higher than SPP_CHOICES[0]. Tessera's filter-importance-sampled
# image is ~1.8x noisier than Mitsuba's splatted one (box_factor), so at the first spp where two
# Mitsuba seeds agree its own image mean may still stray past the test's 0.5 %:
# bsdf_thindielectric_glass at 256 spp was 0.62 % off in blue (seed 0), and 0.05 % off at 2048 spp
# (seed 3), i.e. noise, not bias.
MIN_SPP = {"bsdf_thindielectric_glass": 512}

SCENES = [
    "bsdf_diffuse_textured",
    "bsdf_roughconductor_copper",
    "bsdf_roughconductor_textured_carbon",
    "bsdf_conductor_gold",
    "bsdf_dielectric_glass",
    "bsdf_roughdielectric_rough",
    "bsdf_thindielectric_glass",
    "bsdf_plastic_shiny",
    "bsdf_roughplastic_ggx",
    "bsdf_normalmap_with",
    "bsdf_bumpmap_with",
    "bsdf_mask_after",
    "bsdf_twosided_cbox",
]


def small_size(scene):
    """WIDTH x HEIGHT, or for a film of another aspect ratio WIDTH x the height that keeps it
    (recorded per scene in references.json)."""
    size = scene.sensors()[0].film().size()
    if abs(size[0] / size[1] - WIDTH / HEIGHT) <= 1e-6:
        return WIDTH, HEIGHT
    height = WIDTH * size[1] / size[0]
    if abs(height - round(height)) > 1e-6:
        raise SystemExit("aspect ratio %s gives no whole height at width %d" % (size, WIDTH))
    return WIDTH, int(round(height))


def small_sensor(scene, spp, rfilter):
    """The scene's camera at small_size(scene) with `spp` and the pixel filter `rfilter`."""
    sensor = scene.sensors()[0]
    params = mi.traverse(sensor)
    width, height = small_size(scene)
    fov_x = float(np.array(params["x_fov"]).ravel()[0])
    return mi.load_dict({
        "type": "perspective",
        "fov_axis": "x",
        "fov": fov_x,
        "near_clip": float(np.array(params["near_clip"]).ravel()[0]),
        "to_world": mi.ScalarTransform4f(np.array(sensor.world_transform().matrix).reshape(4, 4)),
        "film": {"type": "hdrfilm", "width": width, "height": height, "pixel_format": "rgb",
                 "rfilter": rfilter},
        "sampler": {"type": "independent", "sample_count": spp},
    })


def filter_of(scene):
    rf = str(scene.sensors()[0].film().rfilter()).lower()
    for kind in ("gaussian", "tent", "box"):
        if rf.startswith(kind):
            return kind
    raise SystemExit("unknown filter %s" % rf)


def render(scene, sensor, seed):
    return np.array(mi.render(scene, sensor=sensor, seed=seed, spp=0), dtype=np.float64)


def inner(img):
    return img[BORDER:-BORDER, BORDER:-BORDER, :3]


def rmse(a, b):
    return float(np.sqrt(np.mean((inner(a) - inner(b)) ** 2)))


def main():
    mi.set_variant("llvm_ad_rgb")
    os.makedirs(OUT, exist_ok=True)
    table = {"width": WIDTH, "height": HEIGHT, "ref_factor": REF_FACTOR, "border": BORDER,
             "mitsuba": mi.__version__, "scenes": {}}
    for name in sys.argv[1:] or SCENES:
        t0 = time.time()
        scene = mi.load_file(os.path.join(SCENES_DIR, name + ".xml"))
        kind = filter_of(scene)
        rf = {"type": kind}
        for spp in (c for c in SPP_CHOICES if c >= MIN_SPP.get(name, 0)):
            test_sensor = small_sensor(scene, spp, rf)
            runs = [render(scene, test_sensor, s) for s in range(2)]
            means = [inner(r).mean(axis=(0, 1)) for r in runs]
            mean_gap = float(np.max(np.abs(means[0] - means[1]) / np.maximum((means[0] + means[1]) / 2, 1e-9)))
            if mean_gap <= 0.002:
                break
        ref = render(scene, small_sensor(scene, REF_FACTOR * spp, rf), 1000)
        mi.Bitmap(ref.astype(np.float32)).write(os.path.join(OUT, name + ".exr"))
        runs += [render(scene, test_sensor, s) for s in (2, 3)]
        errors = [rmse(r, ref) for r in runs]
        width, height = small_size(scene)
        entry = {"filter": kind, "spp": spp, "ref_spp": REF_FACTOR * spp,
                 "mitsuba_rmse": statistics.median(errors), "mitsuba_rmse_seeds": errors,
                 "seed_mean_gap": mean_gap, "mean": inner(ref).mean(axis=(0, 1)).tolist(),
                 "nan": bool(np.isnan(ref).any())}
        if (width, height) != (WIDTH, HEIGHT):
            entry["width"], entry["height"] = width, height
        if kind != "box":
            # Noise growth from splatting to one-pixel samples: box-filtered renders at the
            # same spp against a box-filtered reference, two seeds each way.
            box = {"type": "box"}
            box_ref = render(scene, small_sensor(scene, REF_FACTOR * spp, box), 2000)
            box_err = [rmse(render(scene, small_sensor(scene, spp, box), s), box_ref) for s in (10, 11)]
            fil_err = errors[:2]
            entry["box_factor"] = float(np.mean(box_err) / np.mean(fil_err))
        else:
            entry["box_factor"] = 1.0
        entry["seconds"] = time.time() - t0
        table["scenes"][name] = entry
        print(name, json.dumps(entry), flush=True)
        if mean_gap > 0.002:
            print("  warning: seeds differ by %.3f %% in mean at %d spp" % (100 * mean_gap, spp))
    path = os.path.join(OUT, "references.json")
    if sys.argv[1:] and os.path.exists(path):
        old = json.load(open(path))
        old["scenes"].update(table["scenes"])
        table = old
    json.dump(table, open(path, "w"), indent=1, sort_keys=True)


if __name__ == "__main__":
    main()
