#!/usr/bin/env python3
"""Directional albedo of Mitsuba 3's `principled` BSDF: the reference table principled_test.cpp
reads (mitsuba_principled_albedo.txt).

The albedo for the direction wo is the mean of sample()'s weight f |cos wi| / pdf times eta^2
(energy, not radiance: the 1 / eta^2 of a refraction is undone), estimated with 2^20
independent samples in Mitsuba's llvm_ad_rgb variant, with its standard error. The parameter
combinations are those of mitsuba_principled.py (CASES), white or coloured; wo = (sin t cos 30deg,
sin t sin 30deg, cos t), from below too where the BSDF transmits.

Usage: $PY worker/render/bsdf/mitsuba_principled_albedo.py \
           > worker/render/bsdf/mitsuba_principled_albedo.txt
(PY: a Python with Mitsuba 3.9.1.)
"""
import mitsuba as mi

from mitsuba_points import albedo
from mitsuba_principled import CASES, DEFAULTS, RATES, WEIGHTS

mi.set_variant("llvm_ad_rgb")  # after the import, which selects scalar_rgb


def main():
    print("# Directional albedo (energy) of Mitsuba 3.9.1's principled BSDF (llvm_ad_rgb), written")
    print("# by mitsuba_principled_albedo.py. Columns: base_r base_g base_b " + " ".join(WEIGHTS) +
          " eta " + " ".join(RATES))
    print("# cos_theta_o albedo_r albedo_g albedo_b se_r se_g se_b")
    seed = 0
    for base, weights, eta, rates in CASES:
        for white in [False, True]:
            color = [1.0, 1.0, 1.0] if white else base
            d = {"type": "principled", "base_color": {"type": "rgb", "value": color}, "eta": eta}
            d.update(weights)
            d.update(rates)
            values = [weights.get(w, DEFAULTS.get(w, 0.0)) for w in WEIGHTS]
            params = " ".join(f"{x:.9g}" for x in color + values + [eta] +
                              [rates.get(r, 1.0) for r in RATES])
            cosines = [1.0, 0.7, 0.3, 0.1]
            if weights.get("spec_trans", 0) != 0:
                cosines += [-1.0, -0.7, -0.3]
            for c in cosines:
                res = albedo(d, c, seed)
                seed += 1
                vals = " ".join(f"{m:.6f}" for m, _ in res)
                ses = " ".join(f"{s:.1e}" for _, s in res)
                print(f"{params} {c} {vals} {ses}", flush=True)


if __name__ == "__main__":
    main()
