#!/usr/bin/env python3
"""Reference values of Mitsuba 3's `blendbsdf`, read by blend_test.cpp.

`points` (mitsuba_blend.txt): three blends of smooth lobes (their parameters are repeated in
blend_test.cpp, case by case): a rough conductor and a diffuse BSDF, a rough dielectric and a
diffuse BSDF (both sides), and a blend nesting the second and a principled metal; eval() and
pdf() at the direction pairs of mitsuba_points.py, scalar_rgb.
`albedo` (mitsuba_blend_albedo.txt): the mean of sample()'s weight (2^20 samples, llvm_ad_rgb)
for blends of a perfectly specular lobe with a smooth one (ALBEDO_CASES; bsdf_blendbsdf.xml's
rough plastic and gold among them) and one of smooth lobes only. Mitsuba weights a specular
sample by the mixture of its lobe's probability and the other BSDF's density, which makes these
blends darker than (1 - w) first + w second: the table pins that down.

Usage (PY: a Python with Mitsuba 3.9.1), from worker/render/bsdf/:
  $PY mitsuba_blend.py points > mitsuba_blend.txt
  $PY mitsuba_blend.py albedo > mitsuba_blend_albedo.txt
"""
import sys

import mitsuba as mi

from mitsuba_points import rgb

DIFFUSE = {"type": "diffuse", "reflectance": rgb([0.7, 0.5, 0.3])}
METAL = {"type": "roughconductor", "distribution": "ggx", "alpha": 0.2,
         "eta": rgb([0.2, 0.9, 1.1]), "k": rgb([3.9, 2.4, 2.2])}
GLASS = {"type": "roughdielectric", "distribution": "beckmann", "alpha": 0.3, "int_ior": 1.5,
         "ext_ior": 1.0}
PRINCIPLED_METAL = {"type": "principled", "base_color": rgb([0.9, 0.6, 0.3]),
                    "metallic": 1.0, "roughness": 0.4, "eta": 1.5}
GLASS_AND_DIFFUSE = {"type": "blendbsdf", "weight": 0.6, "a": GLASS, "b": DIFFUSE}
CASES = [
    {"type": "blendbsdf", "weight": 0.3, "a": METAL, "b": DIFFUSE},
    GLASS_AND_DIFFUSE,
    {"type": "blendbsdf", "weight": 0.25, "a": GLASS_AND_DIFFUSE, "b": PRINCIPLED_METAL},
]

# bsdf_blendbsdf.xml's pair: a black rough plastic and a smooth gold-like conductor.
BLACK_PLASTIC = {"type": "roughplastic", "distribution": "ggx", "alpha": 0.3,
                 "diffuse_reflectance": rgb([0.0, 0.0, 0.0])}
SMOOTH_METAL = {"type": "conductor", "eta": rgb([0.2, 0.9, 1.1]), "k": rgb([3.9, 2.4, 2.2])}
SMOOTH_GLASS = {"type": "dielectric", "int_ior": 1.5, "ext_ior": 1.0}
PLASTIC = {"type": "plastic", "int_ior": 1.5, "ext_ior": 1.0,
           "diffuse_reflectance": rgb([0.8, 0.5, 0.2])}
# (case, weight): repeated in blend_test.cpp's albedo_case().
ALBEDO_CASES = [
    ("plastic+conductor", 0.5, BLACK_PLASTIC, SMOOTH_METAL),
    ("plastic+conductor", 0.25, BLACK_PLASTIC, SMOOTH_METAL),
    ("plastic+conductor", 0.9, BLACK_PLASTIC, SMOOTH_METAL),
    ("diffuse+glass", 0.6, DIFFUSE, SMOOTH_GLASS),
    ("diffuse+plastic", 0.4, DIFFUSE, PLASTIC),
    ("metal+diffuse", 0.3, METAL, DIFFUSE),
]


def points():
    mi.set_variant("scalar_rgb")
    import mitsuba_points
    print("# Point values of Mitsuba 3.9.1's blendbsdf (scalar_rgb), written by mitsuba_blend.py.")
    print("# Columns: case wo_x wo_y wo_z wi_x wi_y wi_z eval_r eval_g eval_b pdf")
    for index, case in enumerate(CASES):
        for row in mitsuba_points.point_rows(case):
            print(f"{index} {row}")


def albedo():
    mi.set_variant("llvm_ad_rgb")
    import mitsuba_points
    print("# Directional albedo (energy) of Mitsuba 3.9.1's blendbsdf (llvm_ad_rgb), written by")
    print("# mitsuba_blend.py albedo. Columns: case weight cos_theta_o albedo_r albedo_g albedo_b")
    print("# se_r se_g se_b")
    seed = 0
    for name, weight, first, second in ALBEDO_CASES:
        d = {"type": "blendbsdf", "weight": weight, "a": first, "b": second}
        for c in [1.0, 0.7, 0.3]:
            res = mitsuba_points.albedo(d, c, seed)
            seed += 1
            vals = " ".join(f"{m:.6f}" for m, _ in res)
            ses = " ".join(f"{s:.1e}" for _, s in res)
            print(f"{name} {weight} {c} {vals} {ses}", flush=True)


if __name__ == "__main__":
    {"points": points, "albedo": albedo}[sys.argv[1] if len(sys.argv) > 1 else "points"]()
