#!/usr/bin/env python3
"""Point values of Mitsuba 3's `principled` BSDF: the reference table principled_test.cpp reads.

For a set of parameter combinations (every lobe on and off, anisotropy, transmission from both
sides, eta above and below 1, the three sampling rates) and fixed pairs of directions (wo
towards the camera, wi the other one, local frame; Mitsuba calls them si.wi and wo) it writes
eval() = f |cos wi| per channel and pdf(), in the scalar_rgb variant and radiance transport.

Usage: $PY worker/render/bsdf/mitsuba_principled.py \
           > worker/render/bsdf/mitsuba_principled.txt
(PY: a Python with Mitsuba 3.9.1.)
"""
import mitsuba as mi

mi.set_variant("scalar_rgb")

import mitsuba_points  # noqa: E402 (after the variant)

WEIGHTS = ["roughness", "anisotropic", "metallic", "spec_trans", "spec_tint", "sheen",
           "sheen_tint", "flatness", "clearcoat", "clearcoat_gloss"]
RATES = ["main_specular_sampling_rate", "clearcoat_sampling_rate",
         "diffuse_reflectance_sampling_rate"]

# Each case: base_color, the weights given (the others keep Mitsuba's defaults), eta, rates.
CASES = [
    ([0.8, 0.5, 0.2], {}, 1.5, {}),
    ([0.8, 0.5, 0.2], {"roughness": 0.3, "anisotropic": 0.6, "metallic": 0.7, "spec_tint": 0.4},
     1.5, {}),
    ([0.3, 0.6, 0.9], {"roughness": 0.2, "spec_trans": 0.8}, 1.5, {}),
    ([0.3, 0.6, 0.9], {"roughness": 0.35, "spec_trans": 1.0}, 0.75, {}),
    ([0.8, 0.5, 0.2], {"roughness": 0.7, "sheen": 0.8, "sheen_tint": 0.5, "flatness": 0.6,
                       "clearcoat": 0.7, "clearcoat_gloss": 0.4}, 1.5, {}),
    ([0.6, 0.2, 0.4], {"roughness": 0.4, "anisotropic": 0.4, "metallic": 0.3, "spec_trans": 0.5,
                       "spec_tint": 0.6, "sheen": 0.4, "flatness": 0.3, "clearcoat": 1.0,
                       "clearcoat_gloss": 0.9}, 1.33,
     {"main_specular_sampling_rate": 0.5, "clearcoat_sampling_rate": 2.0,
      "diffuse_reflectance_sampling_rate": 1.5}),
    ([0.9, 0.9, 0.9], {"roughness": 1.0, "metallic": 1.0}, 1.5, {}),
    ([0.0, 0.0, 0.0], {"roughness": 0.05, "spec_tint": 1.0, "sheen": 1.0, "sheen_tint": 1.0}, 2.0,
     {}),
]

DEFAULTS = {"roughness": 0.5}


def main():
    print("# Point values of Mitsuba 3.9.1's principled BSDF (scalar_rgb), written by")
    print("# mitsuba_principled.py. Columns: base_r base_g base_b " + " ".join(WEIGHTS) +
          " eta " + " ".join(RATES))
    print("# wo_x wo_y wo_z wi_x wi_y wi_z eval_r eval_g eval_b pdf")
    for base, weights, eta, rates in CASES:
        d = {"type": "principled", "base_color": {"type": "rgb", "value": base}, "eta": eta}
        d.update(weights)
        d.update(rates)
        values = [weights.get(w, DEFAULTS.get(w, 0.0)) for w in WEIGHTS]
        params = " ".join(f"{x:.9g}" for x in base + values + [eta] +
                          [rates.get(r, 1.0) for r in RATES])
        for row in mitsuba_points.point_rows(d):
            print(f"{params} {row}")

if __name__ == "__main__":
    main()
