#!/usr/bin/env python3
"""Point values of Mitsuba 3's BSDFs: the reference table eval_test.cpp reads.

For a set of BSDFs (pplastic as the RGB variants render it) and fixed pairs of directions (wo towards the camera, wi the other one, in
the local frame; Mitsuba calls them si.wi and wo) it writes eval() = f |cos wi| per channel and
pdf(), in the scalar_rgb variant and radiance transport.

Usage: $PY worker/render/bsdf/mitsuba_eval.py > worker/render/bsdf/mitsuba_eval.txt
(PY: a Python with Mitsuba 3.9.1.)
"""
import mitsuba as mi

mi.set_variant("scalar_rgb")

import mitsuba_points  # noqa: E402 (after the variant)
from mitsuba_points import rgb  # noqa: E402

CONDUCTOR_ETA = [0.2, 0.9, 1.1]
CONDUCTOR_K = [3.9, 2.4, 2.2]
PLASTIC_DIFFUSE = [0.8, 0.5, 0.2]


# mitsuba_points.PAIRS less its two pairs that graze from below.
PAIRS = [p for i, p in enumerate(mitsuba_points.PAIRS) if i not in (7, 11)]


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
    # pplastic as the RGB variants render it (no polarization).
    for dist in ["beckmann", "ggx"]:
        for au, av in [(0.3, 0.3), (0.1, 0.5)]:
            for sv in [True, False]:
                yield ("pplastic", dist, au, av, 1.5, 0, int(sv),
                       {"type": "pplastic", "distribution": dist, "alpha_u": au, "alpha_v": av,
                        "sample_visible": sv, "int_ior": 1.5, "ext_ior": 1.0,
                        "diffuse_reflectance": rgb(PLASTIC_DIFFUSE)})


def main():
    print("# Point values of Mitsuba 3.9.1 BSDFs (scalar_rgb), written by mitsuba_eval.py.")
    print(f"# conductor eta {CONDUCTOR_ETA} k {CONDUCTOR_K}; plastics and diffuse reflectance {PLASTIC_DIFFUSE}.")
    print("# Columns: type distribution alpha_u alpha_v eta nonlinear sample_visible wo_x wo_y wo_z")
    print("# wi_x wi_y wi_z eval_r eval_g eval_b pdf")
    for kind, dist, au, av, eta, nl, sv, d in bsdfs():
        for row in mitsuba_points.point_rows(d, PAIRS):
            print(f"{kind} {dist} {au} {av} {eta} {nl} {sv} {row}")

if __name__ == "__main__":
    main()
