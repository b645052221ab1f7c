#!/usr/bin/env python3
"""Reference values of Mitsuba 3's `principledthin` BSDF, read by principled_thin_test.cpp.

`points` (mitsuba_principled_thin.txt): for each parameter combination of CASES (every lobe on
and off, anisotropy, spec_tint, diff_trans up to 2, eta above and below 1, the sampling rates)
and the fixed direction pairs of mitsuba_points.py, from both sides of the sheet, eval() and
pdf() in the scalar_rgb variant.
`albedo` (mitsuba_principled_thin_albedo.txt): the mean of sample()'s weight (2^20 samples,
llvm_ad_rgb) and its standard error, for each case coloured and white, from both sides.
`samples` (mitsuba_principled_thin_sample.txt): sample() for given random numbers (u_lobe, u),
16 per case of SAMPLE_CASES from both sides, scalar_rgb: Tessera uses the random numbers as
Mitsuba does. SAMPLE_CASES leaves out lobes sharper than GGX alpha 0.04: there the two
renderers' float visible-normal samplers (1 - cos^2 of a nearly normal stretched direction)
part by up to ~1e-3 in direction, while eval() and pdf() agree to 1e-6 (`points`).

Usage (PY: a Python with Mitsuba 3.9.1), from worker/render/bsdf/:
  $PY mitsuba_principled_thin.py points > mitsuba_principled_thin.txt
  $PY mitsuba_principled_thin.py albedo > mitsuba_principled_thin_albedo.txt
  $PY mitsuba_principled_thin.py samples > mitsuba_principled_thin_sample.txt
"""
import math
import random
import sys

import mitsuba as mi

WEIGHTS = ["roughness", "anisotropic", "spec_trans", "spec_tint", "sheen", "sheen_tint",
           "flatness", "diff_trans"]
RATES = ["diffuse_reflectance_sampling_rate", "specular_reflectance_sampling_rate",
         "specular_transmittance_sampling_rate", "diffuse_transmittance_sampling_rate"]
DEFAULTS = {"roughness": 0.5}

# Each case: base_color, the weights given (the others keep Mitsuba's defaults), eta, rates.
CASES = [
    ([0.8, 0.5, 0.2], {}, 1.5, {}),
    ([0.3, 0.6, 0.9], {"roughness": 0.3, "anisotropic": 0.5, "spec_trans": 0.8, "spec_tint": 0.4},
     1.33, {}),
    ([0.6, 0.2, 0.4], {"roughness": 0.7, "spec_trans": 0.3, "sheen": 0.6, "sheen_tint": 0.5,
                       "flatness": 0.5, "diff_trans": 1.4}, 1.5,
     {"diffuse_reflectance_sampling_rate": 0.5, "specular_reflectance_sampling_rate": 2.0,
      "specular_transmittance_sampling_rate": 1.5, "diffuse_transmittance_sampling_rate": 0.7}),
    ([0.9, 0.9, 0.9], {"roughness": 0.25, "spec_trans": 1.0}, 1.2, {}),
    ([0.7, 0.5, 0.3], {"diff_trans": 2.0}, 1.5, {}),
    ([0.0, 0.0, 0.0], {"roughness": 0.15, "spec_trans": 0.5, "spec_tint": 1.0, "sheen": 1.0,
                       "sheen_tint": 1.0}, 0.8, {}),
]


# For `samples`: CASES whose GGX lobes are no sharper than alpha 0.04, and two more.
MIN_SAMPLE_ALPHA = 0.04


def sharpest_alpha(base, weights, eta, rates):
    if weights.get("spec_trans", 0.0) == 0.0:
        return 1.0
    r = weights.get("roughness", DEFAULTS["roughness"])
    aspect = math.sqrt(1.0 - 0.9 * weights.get("anisotropic", 0.0))
    scaled = (0.65 * eta - 0.35) * r
    return min(r * r * aspect, scaled * scaled * aspect)


SAMPLE_CASES = [c for c in CASES if sharpest_alpha(*c) >= MIN_SAMPLE_ALPHA] + [
    ([0.3, 0.6, 0.9], {"roughness": 0.8, "anisotropic": 0.5, "spec_trans": 0.8, "spec_tint": 0.4},
     1.33, {}),
    ([0.6, 0.4, 0.2], {"roughness": 0.6, "spec_trans": 0.6, "diff_trans": 0.8, "sheen": 0.3},
     1.8, {"specular_transmittance_sampling_rate": 2.0}),
]


def bsdf_dict(base, weights, eta, rates):
    d = {"type": "principledthin", "base_color": {"type": "rgb", "value": base}, "eta": eta}
    d.update(weights)
    d.update(rates)
    return d


def params_text(base, weights, eta, rates):
    values = [weights.get(w, DEFAULTS.get(w, 0.0)) for w in WEIGHTS]
    return " ".join(f"{x:.9g}" for x in base + values + [eta] + [rates.get(r, 1.0) for r in RATES])


def columns():
    return "base_r base_g base_b " + " ".join(WEIGHTS) + " eta " + " ".join(RATES)


def points():
    mi.set_variant("scalar_rgb")
    import mitsuba_points
    print("# Point values of Mitsuba 3.9.1's principledthin BSDF (scalar_rgb), written by")
    print("# mitsuba_principled_thin.py points. Columns: " + columns())
    print("# wo_x wo_y wo_z wi_x wi_y wi_z eval_r eval_g eval_b pdf")
    for case in CASES:
        for row in mitsuba_points.point_rows(bsdf_dict(*case)):
            print(f"{params_text(*case)} {row}")


def albedo():
    mi.set_variant("llvm_ad_rgb")
    import mitsuba_points
    print("# Directional albedo of Mitsuba 3.9.1's principledthin BSDF (llvm_ad_rgb), written by")
    print("# mitsuba_principled_thin.py albedo. Columns: " + columns())
    print("# cos_theta_o albedo_r albedo_g albedo_b se_r se_g se_b")
    seed = 0
    for base, weights, eta, rates in CASES:
        for color in [base, [1.0, 1.0, 1.0]]:
            for c in [1.0, 0.7, 0.3, 0.1, -0.6]:
                res = mitsuba_points.albedo(bsdf_dict(color, weights, eta, rates), c, seed)
                seed += 1
                vals = " ".join(f"{m:.6f}" for m, _ in res)
                ses = " ".join(f"{s:.1e}" for _, s in res)
                print(f"{params_text(color, weights, eta, rates)} {c} {vals} {ses}", flush=True)


def samples():
    mi.set_variant("scalar_rgb")
    print("# Samples of Mitsuba 3.9.1's principledthin BSDF (scalar_rgb), written by")
    print("# mitsuba_principled_thin.py samples. Columns: " + columns())
    print("# wo_x wo_y wo_z u_lobe u_x u_y wi_x wi_y wi_z weight_r weight_g weight_b pdf")
    print("# (weight 0: no sample)")
    rng = random.Random(7)
    ctx = mi.BSDFContext()
    for case in SAMPLE_CASES:
        bsdf = mi.load_dict(bsdf_dict(*case))
        for _ in range(16):
            theta = rng.uniform(0.05, 1.45)
            if rng.random() < 0.4:
                theta = math.pi - theta
            phi = rng.uniform(0, 2 * math.pi)
            wo = [math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta)]
            u = [rng.random() for _ in range(3)]
            si = mi.SurfaceInteraction3f()
            si.wi = mi.Vector3f(wo)
            bs, weight = bsdf.sample(ctx, si, u[0], mi.Point2f(u[1], u[2]))
            fields = wo + u + [bs.wo[0], bs.wo[1], bs.wo[2]] + [weight[c] for c in range(3)] + [bs.pdf]
            print(params_text(*case) + " " + " ".join(f"{float(x):.9g}" for x in fields))


if __name__ == "__main__":
    {"points": points, "albedo": albedo, "samples": samples}[sys.argv[1] if len(sys.argv) > 1 else "points"]()
