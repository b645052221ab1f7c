#!/usr/bin/env python3
"""Reference values of Mitsuba 3's `hair` BSDF in the scalar_rgb variant, read by hair_test.cpp:
for each case (its parameters) and each pair (wo, wi) of mitsuba_points.py (the hair takes
directions all around the fibre: both sides are used), eval() and pdf() at the pair, and
sample() for fixed random numbers (sample1 and sample2 varying with the pair).

In the local frame +x runs around the fibre, +y along it and +z is the normal.

Usage (PY: a Python with Mitsuba 3.9.1), from worker/render/bsdf/:
  $PY mitsuba_hair.py > mitsuba_hair.txt
"""
import mitsuba as mi

mi.set_variant("scalar_rgb")

from mitsuba_points import PAIRS, direction  # noqa: E402

# name, Mitsuba parameters, and the same as the columns Tessera reads: sigma_a (r g b, resolved),
# eta, longitudinal roughness, azimuthal roughness, scale tilt (degrees).
AIR = 1.000277
CASES = [
    ({}, [1.3 * 0.419 + 0.2 * 0.187, 1.3 * 0.697 + 0.2 * 0.4, 1.3 * 1.37 + 0.2 * 1.05],
     1.55 / AIR, 0.3, 0.3, 2.0),
    ({"eumelanin": 0.3, "pheomelanin": 0.2},
     [0.3 * 0.419 + 0.2 * 0.187, 0.3 * 0.697 + 0.2 * 0.4, 0.3 * 1.37 + 0.2 * 1.05],
     1.55 / AIR, 0.3, 0.3, 2.0),
    ({"sigma_a": {"type": "rgb", "value": [0.2, 0.5, 1.0]}, "scale": 2.0,
      "longitudinal_roughness": 0.1, "azimuthal_roughness": 0.6, "scale_tilt": 5.0,
      "int_ior": 1.3, "ext_ior": 1.0},
     [0.4, 1.0, 2.0], 1.3, 0.1, 0.6, 5.0),
    ({"sigma_a": {"type": "rgb", "value": [0.0, 0.0, 0.0]}, "longitudinal_roughness": 1.0,
      "azimuthal_roughness": 1.0, "scale_tilt": 0.0},
     [0.0, 0.0, 0.0], 1.55 / AIR, 1.0, 1.0, 0.0),
    ({"eumelanin": 0.01, "pheomelanin": 1.6, "longitudinal_roughness": 0.05,
      "azimuthal_roughness": 0.05},
     [0.01 * 0.419 + 1.6 * 0.187, 0.01 * 0.697 + 1.6 * 0.4, 0.01 * 1.37 + 1.6 * 1.05],
     1.55 / AIR, 0.05, 0.05, 2.0),
]

print("# Mitsuba 3.9.1's hair BSDF (scalar_rgb), written by mitsuba_hair.py.")
print("# Columns: sigma_a_r sigma_a_g sigma_a_b eta beta_m beta_n alpha_deg wo_x wo_y wo_z "
      "wi_x wi_y wi_z eval_r eval_g eval_b pdf u_lobe u_x u_y sampled_x sampled_y sampled_z "
      "weight_r weight_g weight_b sampled_pdf")
for params, sigma_a, eta, bm, bn, alpha in CASES:
    bsdf = mi.load_dict({"type": "hair", **params})
    ctx = mi.BSDFContext()
    for k, (to, po, ti, pi) in enumerate(PAIRS):
        wo, wi = direction(to, po), direction(ti, pi)
        si = mi.SurfaceInteraction3f()
        si.wi = mi.Vector3f(wo)
        value = bsdf.eval(ctx, si, mi.Vector3f(wi))
        pdf = bsdf.pdf(ctx, si, mi.Vector3f(wi))
        u_lobe, u = 0.05 + 0.08 * k, [0.3 + 0.05 * k, 0.9 - 0.07 * k]
        bs, weight = bsdf.sample(ctx, si, u_lobe, mi.Point2f(u))
        cols = sigma_a + [eta, bm, bn, alpha] + wo + wi + [value[c] for c in range(3)] + [pdf]
        cols += [u_lobe] + u + [bs.wo[i] for i in range(3)] + [weight[c] for c in range(3)]
        cols += [bs.pdf]
        print(" ".join(f"{float(x):.9g}" for x in cols))
