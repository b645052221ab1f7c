#!/usr/bin/env python3
"""Point values of Mitsuba 3's `blendbsdf`: the reference table blend_test.cpp reads.

Three blends (their parameters are repeated in blend_test.cpp, case by case): a rough conductor
and a diffuse BSDF, a rough dielectric and a diffuse BSDF (both sides), and a blend nesting the
second and a principled metal. For fixed pairs of directions (wo towards the camera, wi the other
one, local frame; Mitsuba's si.wi and wo) it writes eval() = f |cos wi| per channel and pdf(), in
the scalar_rgb variant and radiance transport.

Usage: /work/venv-mitsuba/bin/python worker/render/bsdf/mitsuba_blend.py \
           > worker/render/bsdf/mitsuba_blend.txt
(Mitsuba 3.9.1.)
"""
import mitsuba as mi

from mitsuba_principled import PAIRS, direction

mi.set_variant("scalar_rgb")

DIFFUSE = {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.7, 0.5, 0.3]}}
METAL = {"type": "roughconductor", "distribution": "ggx", "alpha": 0.2,
         "eta": {"type": "rgb", "value": [0.2, 0.9, 1.1]}, "k": {"type": "rgb", "value": [3.9, 2.4, 2.2]}}
GLASS = {"type": "roughdielectric", "distribution": "beckmann", "alpha": 0.3, "int_ior": 1.5,
         "ext_ior": 1.0}
PRINCIPLED_METAL = {"type": "principled", "base_color": {"type": "rgb", "value": [0.9, 0.6, 0.3]},
                    "metallic": 1.0, "roughness": 0.4, "eta": 1.5}
GLASS_AND_DIFFUSE = {"type": "blendbsdf", "weight": 0.6, "a": GLASS, "b": DIFFUSE}
CASES = [
    {"type": "blendbsdf", "weight": 0.3, "a": METAL, "b": DIFFUSE},
    GLASS_AND_DIFFUSE,
    {"type": "blendbsdf", "weight": 0.25, "a": GLASS_AND_DIFFUSE, "b": PRINCIPLED_METAL},
]


def main():
    print("# Point values of Mitsuba 3.9.1's blendbsdf (scalar_rgb), written by mitsuba_blend.py.")
    print("# Columns: case wo_x wo_y wo_z wi_x wi_y wi_z eval_r eval_g eval_b pdf")
    ctx = mi.BSDFContext()
    for index, case in enumerate(CASES):
        bsdf = mi.load_dict(case)
        for to, po, ti, pi in PAIRS:
            wo, wi = direction(to, po), direction(ti, pi)
            si = mi.SurfaceInteraction3f()
            si.wi = mi.Vector3f(wo)
            value = bsdf.eval(ctx, si, mi.Vector3f(wi))
            pdf = bsdf.pdf(ctx, si, mi.Vector3f(wi))
            dirs = " ".join(f"{x:.9g}" for x in wo + wi)
            vals = " ".join(f"{float(value[c]):.9g}" for c in range(3))
            print(f"{index} {dirs} {vals} {float(pdf):.9g}")


if __name__ == "__main__":
    main()
