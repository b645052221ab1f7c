#!/usr/bin/env python3
"""Point values of Mitsuba 3's BSDFs: the reference table eval_test.cpp reads.

For a set of BSDFs and fixed pairs of directions (wo towards the camera, wi the other one, in
the local frame; Mitsuba calls them si.wi and wo) it writes eval() = f |cos wi| per channel and
pdf(), in the scalar_rgb variant and radiance transport.

Usage: /work/venv-mitsuba/bin/python worker/render/bsdf/mitsuba_eval.py > worker/render/bsdf/mitsuba_eval.txt
(Mitsuba 3.9.1.)
"""
import math

import mitsuba as mi

mi.set_variant("scalar_rgb")

CONDUCTOR_ETA = [0.2, 0.9, 1.1]
CONDUCTOR_K = [3.9, 2.4, 2.2]
PLASTIC_DIFFUSE = [0.8, 0.5, 0.2]


def rgb(v):
    return {"type": "rgb", "value": v}


def direction(theta, phi):
    return [math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta)]


# (theta_o, phi_o, theta_i, phi_i) in radians: reflections near and far from the mirror
# direction, grazing ones, and pairs across the surface (used by the dielectric).
PAIRS = [
    (0.3, 0.2, 0.35, 0.2 + math.pi),
    (0.7, 0.5, 0.6, 0.5 + math.pi + 0.3),
    (1.2, 1.0, 0.2, 2.0),
    (1.45, 0.1, 1.4, math.pi + 0.2),
    (0.0, 0.0, 0.9, 0.7),
    (0.5, 0.3, math.pi - 0.3, 0.3 + math.pi),
    (1.0, 2.0, math.pi - 0.6, 2.0 + math.pi + 0.2),
    (math.pi - 0.4, 0.5, math.pi - 0.5, 0.5 + math.pi),
    (math.pi - 0.3, 1.0, 0.5, 1.0 + math.pi),
    (math.pi - 0.2, 1.5, 1.1, 1.5 + math.pi + 0.1),
]


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
        for sv in [True, False]:
            for nonlinear in [False, True]:
                yield ("rough_plastic", dist, 0.3, 0.3, 1.5, int(nonlinear), int(sv),
                       {"type": "roughplastic", "distribution": dist, "alpha": 0.3, "sample_visible": sv,
                        "int_ior": 1.5, "ext_ior": 1.0, "nonlinear": nonlinear,
                        "diffuse_reflectance": rgb(PLASTIC_DIFFUSE)})
    for nonlinear in [False, True]:
        yield ("plastic", "none", 0.0, 0.0, 1.5, int(nonlinear), 1,
               {"type": "plastic", "int_ior": 1.5, "ext_ior": 1.0, "nonlinear": nonlinear,
                "diffuse_reflectance": rgb(PLASTIC_DIFFUSE)})
    yield ("diffuse", "none", 0.0, 0.0, 0.0, 0, 1, {"type": "diffuse", "reflectance": rgb(PLASTIC_DIFFUSE)})


def main():
    print("# Point values of Mitsuba 3.9.1 BSDFs (scalar_rgb), written by mitsuba_eval.py.")
    print(f"# conductor eta {CONDUCTOR_ETA} k {CONDUCTOR_K}; plastics and diffuse reflectance {PLASTIC_DIFFUSE}.")
    print("# Columns: type distribution alpha_u alpha_v eta nonlinear sample_visible wo_x wo_y wo_z")
    print("# wi_x wi_y wi_z eval_r eval_g eval_b pdf")
    ctx = mi.BSDFContext()
    for kind, dist, au, av, eta, nl, sv, d in bsdfs():
        bsdf = mi.load_dict(d)
        for to, po, ti, pi in PAIRS:
            wo, wi = direction(to, po), direction(ti, pi)
            si = mi.SurfaceInteraction3f()
            si.wi = mi.Vector3f(wo)
            value = bsdf.eval(ctx, si, mi.Vector3f(wi))
            pdf = bsdf.pdf(ctx, si, mi.Vector3f(wi))
            dirs = " ".join(f"{x:.9g}" for x in wo + wi)
            vals = " ".join(f"{float(value[c]):.9g}" for c in range(3))
            print(f"{kind} {dist} {au} {av} {eta} {nl} {sv} {dirs} {vals} {float(pdf):.9g}")


if __name__ == "__main__":
    main()
