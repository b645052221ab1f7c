#!/usr/bin/env python3
"""Samples of Mitsuba 3's BSDFs for given random numbers: the reference table sample_test.cpp reads.

Tessera's sample() implements Mitsuba's sampling algorithms with the same use of the random
numbers (u_lobe picks the lobe, u the direction), so the same numbers must give the same
direction, weight and pdf. Scalar_rgb variant, radiance transport.

Usage: $PY worker/render/bsdf/mitsuba_sample.py > worker/render/bsdf/mitsuba_sample.txt
(PY: a Python with Mitsuba 3.9.1.)
"""
import math
import random

import mitsuba as mi

mi.set_variant("scalar_rgb")

CONDUCTOR_ETA = [0.2, 0.9, 1.1]
CONDUCTOR_K = [3.9, 2.4, 2.2]
PLASTIC_DIFFUSE = [0.8, 0.5, 0.2]


def rgb(v):
    return {"type": "rgb", "value": v}


def bsdfs():
    for dist in ["beckmann", "ggx"]:
        for au, av in [(0.3, 0.3), (0.1, 0.5)]:
            for sv in [True, False]:
                yield ("rough_conductor", dist, au, av, 0.0, 0, int(sv),
                       {"type": "roughconductor", "distribution": dist, "alpha_u": au, "alpha_v": av,
                        "sample_visible": sv, "eta": rgb(CONDUCTOR_ETA), "k": rgb(CONDUCTOR_K)})
                yield ("rough_glass", dist, au, av, 1.5, 0, int(sv),
                       {"type": "roughdielectric", "distribution": dist, "alpha_u": au, "alpha_v": av,
                        "sample_visible": sv, "int_ior": 1.5, "ext_ior": 1.0})
        yield ("rough_plastic", dist, 0.3, 0.3, 1.5, 0, 1,
               {"type": "roughplastic", "distribution": dist, "alpha": 0.3, "int_ior": 1.5,
                "ext_ior": 1.0, "diffuse_reflectance": rgb(PLASTIC_DIFFUSE)})
    yield ("plastic", "none", 0.0, 0.0, 1.5, 1, 1,
           {"type": "plastic", "int_ior": 1.5, "ext_ior": 1.0, "nonlinear": True,
            "diffuse_reflectance": rgb(PLASTIC_DIFFUSE)})
    yield ("diffuse", "none", 0.0, 0.0, 0.0, 0, 1, {"type": "diffuse", "reflectance": rgb(PLASTIC_DIFFUSE)})
    yield ("conductor", "none", 0.0, 0.0, 0.0, 0, 1,
           {"type": "conductor", "eta": rgb(CONDUCTOR_ETA), "k": rgb(CONDUCTOR_K)})
    yield ("glass", "none", 0.0, 0.0, 1.5, 0, 1, {"type": "dielectric", "int_ior": 1.5, "ext_ior": 1.0})
    yield ("thin_glass", "none", 0.0, 0.0, 1.5, 0, 1, {"type": "thindielectric", "int_ior": 1.5, "ext_ior": 1.0})
    # pplastic as the RGB variants render it.
    for dist, au, av, sv in [("ggx", 0.1, 0.5, True), ("beckmann", 0.3, 0.3, False)]:
        yield ("pplastic", dist, au, av, 1.5, 0, int(sv),
               {"type": "pplastic", "distribution": dist, "alpha_u": au, "alpha_v": av,
                "sample_visible": sv, "int_ior": 1.5, "ext_ior": 1.0,
                "diffuse_reflectance": rgb(PLASTIC_DIFFUSE)})


def main():
    print("# Samples of Mitsuba 3.9.1 BSDFs (scalar_rgb), written by mitsuba_sample.py.")
    print(f"# conductor eta {CONDUCTOR_ETA} k {CONDUCTOR_K}; plastics and diffuse reflectance {PLASTIC_DIFFUSE}.")
    print("# Columns: type distribution alpha_u alpha_v eta nonlinear sample_visible wo_x wo_y wo_z")
    print("# u_lobe u_x u_y wi_x wi_y wi_z weight_r weight_g weight_b pdf eta (weight 0: no sample)")
    rng = random.Random(5)
    ctx = mi.BSDFContext()
    for kind, dist, au, av, eta, nl, sv, d in bsdfs():
        bsdf = mi.load_dict(d)
        for _ in range(24):
            theta = rng.uniform(0.05, 1.45)
            if rng.random() < 0.35:
                theta = math.pi - theta  # below the surface: only the dielectrics scatter
            phi = rng.uniform(0, 2 * math.pi)
            wo = [math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta)]
            u = [rng.random() for _ in range(3)]
            si = mi.SurfaceInteraction3f()
            si.wi = mi.Vector3f(wo)
            bs, weight = bsdf.sample(ctx, si, u[0], mi.Point2f(u[1], u[2]))
            fields = wo + u + [bs.wo[0], bs.wo[1], bs.wo[2]] + [weight[c] for c in range(3)] + [bs.pdf, bs.eta]
            print(f"{kind} {dist} {au} {av} {eta} {nl} {sv} " + " ".join(f"{float(x):.9g}" for x in fields))


if __name__ == "__main__":
    main()
