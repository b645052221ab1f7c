#!/usr/bin/env python3
"""Directional albedo of Mitsuba 3's rough BSDFs: the reference table albedo_test.cpp reads.

The albedo of a BSDF for the direction wo is the mean of the weight f |cos wi| / pdf of its
sample(), i.e. the fraction of light from wo scattered anywhere (radiance transport: Mitsuba's
default TransportMode, so transmission includes the 1 / eta^2 factor). Each row is estimated
with 2^20 independent samples in Mitsuba's llvm_ad_rgb variant; its standard error is printed
too (below 5e-4), far below the 1 % the test allows.

Usage: $PY worker/render/bsdf/mitsuba_albedo.py > worker/render/bsdf/mitsuba_albedo.txt
(PY: a Python with Mitsuba 3.9.1.)
"""
import mitsuba as mi

mi.set_variant("llvm_ad_rgb")

import mitsuba_points  # noqa: E402 (after the variant)
from mitsuba_points import rgb  # noqa: E402
CONDUCTOR_ETA = [0.2, 0.9, 1.1]  # a gold-like complex index, different per channel
CONDUCTOR_K = [3.9, 2.4, 2.2]
PLASTIC_DIFFUSE = [0.8, 0.5, 0.2]


def rows():
    cosines = [1.0, 0.7, 0.3, 0.1]
    alphas = [(0.05, 0.05), (0.3, 0.3), (1.0, 1.0), (0.05, 0.5)]
    for dist in ["beckmann", "ggx"]:
        for au, av in alphas:
            for sv in [True, False]:
                for c in cosines:
                    d = {"type": "roughconductor", "distribution": dist, "alpha_u": au, "alpha_v": av,
                         "sample_visible": sv, "eta": rgb(CONDUCTOR_ETA), "k": rgb(CONDUCTOR_K)}
                    yield ("rough_conductor", dist, au, av, 0.0, 0, int(sv), c, d)
    for dist in ["beckmann", "ggx"]:
        for au, av in alphas:
            for c in cosines + [-1.0, -0.7, -0.3]:
                d = {"type": "roughdielectric", "distribution": dist, "alpha_u": au, "alpha_v": av,
                     "int_ior": 1.5, "ext_ior": 1.0}
                yield ("rough_glass", dist, au, av, 1.5, 0, 1, c, d)
    for dist in ["beckmann", "ggx"]:
        for a in [0.05, 0.3, 1.0]:
            for nonlinear in [False, True]:
                for c in cosines:
                    d = {"type": "roughplastic", "distribution": dist, "alpha": a, "int_ior": 1.5,
                         "ext_ior": 1.0, "nonlinear": nonlinear, "diffuse_reflectance": rgb(PLASTIC_DIFFUSE)}
                    yield ("rough_plastic", dist, a, a, 1.5, int(nonlinear), 1, c, d)
    for nonlinear in [False, True]:
        for c in cosines:
            d = {"type": "plastic", "int_ior": 1.5, "ext_ior": 1.0, "nonlinear": nonlinear,
                 "diffuse_reflectance": rgb(PLASTIC_DIFFUSE)}
            yield ("plastic", "none", 0.0, 0.0, 1.5, int(nonlinear), 1, c, d)


def main():
    print("# Directional albedo of Mitsuba 3.9.1 BSDFs (llvm_ad_rgb), written by mitsuba_albedo.py.")
    print(f"# conductor eta {CONDUCTOR_ETA} k {CONDUCTOR_K}; plastics diffuse_reflectance {PLASTIC_DIFFUSE};")
    print("# wo = (sin t cos 30deg, sin t sin 30deg, cos t). Columns: type distribution alpha_u alpha_v eta")
    print("# nonlinear sample_visible cos_theta_o albedo_r albedo_g albedo_b se_r se_g se_b")
    for i, (kind, dist, au, av, eta, nl, sv, c, d) in enumerate(rows()):
        res = mitsuba_points.albedo(d, c, seed=i, energy=False)
        vals = " ".join(f"{m:.6f}" for m, _ in res)
        ses = " ".join(f"{s:.1e}" for _, s in res)
        print(f"{kind} {dist} {au} {av} {eta} {nl} {sv} {c} {vals} {ses}", flush=True)


if __name__ == "__main__":
    main()
