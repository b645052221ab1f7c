#!/usr/bin/env python3
"""Reference values of Mitsuba 3's `principledthin` BSDF, read by principled_thin_test.cpp.

`points` (mitsuba_principled_thin.txt): for each parameter combination of CASES (every lobe on
and off, anisotropy, spec_tint, diff_trans up to 2, eta above and below 1, the sampling rates)
and the fixed direction pairs of mitsuba_points.py, from both sides of the sheet, eval() and
pdf() in the scalar_rgb variant.
`albedo` (mitsuba_principled_thin_albedo.txt): the mean of sample()'s weight (2^20 samples,
llvm_ad_rgb) and its standard error, for each case coloured and white, from both sides.

Usage (Mitsuba 3.9.1), from worker/render/bsdf/:
  /work/venv-mitsuba/bin/python mitsuba_principled_thin.py points > mitsuba_principled_thin.txt
  /work/venv-mitsuba/bin/python mitsuba_principled_thin.py albedo > mitsuba_principled_thin_albedo.txt
"""
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


if __name__ == "__main__":
    {"points": points, "albedo": albedo}[sys.argv[1] if len(sys.argv) > 1 else "points"]()
