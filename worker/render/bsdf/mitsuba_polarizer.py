#!/usr/bin/env python3
"""Reference values of Mitsuba 3's `polarizer` BSDF in the scalar_rgb variant (unpolarized),
read by polarizer_test.cpp: for each case (transmittance, theta, polarizing) and direction wo
of mitsuba_points.py's pairs (both sides of the surface), sample() for fixed random numbers,
and eval() / pdf() at the pair's wi (0 for this delta-only BSDF).

Usage (PY: a Python with Mitsuba 3.9.1), from worker/render/bsdf/:
  $PY mitsuba_polarizer.py > mitsuba_polarizer.txt
"""
import mitsuba as mi

mi.set_variant("scalar_rgb")

from mitsuba_points import PAIRS, direction, rgb  # noqa: E402

# transmittance, theta (degrees), polarizing: theta and polarizing must not change RGB values.
CASES = [
    ([1.0, 1.0, 1.0], 0.0, True),
    ([0.8, 0.5, 0.2], 90.0, True),
    ([0.3, 0.6, 0.9], 45.0, False),
    ([0.0, 0.25, 1.0], -30.0, True),
]

print("# Samples of Mitsuba 3.9.1's polarizer BSDF (scalar_rgb), written by mitsuba_polarizer.py.")
print("# Columns: trans_r trans_g trans_b wo_x wo_y wo_z wi_x wi_y wi_z weight_r weight_g "
      "weight_b pdf delta eval_max pdf_at_pair")
for trans, theta, polarizing in CASES:
    bsdf = mi.load_dict({"type": "polarizer", "transmittance": rgb(trans),
                         "theta": {"type": "spectrum", "value": theta},
                         "polarizing": polarizing})
    ctx = mi.BSDFContext()
    for k, (to, po, ti, pi) in enumerate(PAIRS):
        wo, wi_pair = direction(to, po), direction(ti, pi)
        si = mi.SurfaceInteraction3f()
        si.wi = mi.Vector3f(wo)
        bs, weight = bsdf.sample(ctx, si, 0.1 + 0.07 * k, mi.Point2f(0.3, 0.8))
        delta = int(mi.has_flag(bs.sampled_type, mi.BSDFFlags.Delta))
        value = bsdf.eval(ctx, si, mi.Vector3f(wi_pair))
        pdf_pair = bsdf.pdf(ctx, si, mi.Vector3f(wi_pair))
        cols = list(trans) + wo + [bs.wo[i] for i in range(3)] + [weight[c] for c in range(3)]
        cols += [bs.pdf, delta, max(float(value[c]) for c in range(3)), pdf_pair]
        print(" ".join(f"{float(x):.9g}" for x in cols))
