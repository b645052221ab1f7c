"""Reference values for the textured spot light (spot_light_test.cpp) from Mitsuba 3.

Run with a Python that has mitsuba installed (scalar_rgb variant):
    python worker/render/light/mitsuba_spot_reference.py > worker/render/light/mitsuba_spot_reference.inc
It prints C++ table rows: a point (x, y, z) in world space and the radiance Mitsuba's spot
sends to it (sample_direction's value). The spot stands at (1, 2, 3), rotated, with
cutoff_angle 30, beam_width 20, intensity (2, 3, 4) and a 4 x 3 linear float texture
(texel (x, y) = (1 + x + 4 y, 0.5 (x + 1), 0.25 (y + 1)), bilinear, repeat), so every lookup
blends distinct texels and the falloff ramp is crossed.
"""
import math

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")

H, W = 3, 4


def texels():
    data = np.zeros((H, W, 3), dtype=np.float32)
    for y in range(H):
        for x in range(W):
            data[y, x] = [1 + x + 4 * y, 0.5 * (x + 1), 0.25 * (y + 1)]
    return data


def main():
    to_world = (mi.ScalarTransform4f().translate([1.0, 2.0, 3.0])
                @ mi.ScalarTransform4f().rotate([0, 1, 0], 30.0)
                @ mi.ScalarTransform4f().rotate([1, 0, 0], -50.0))
    spot = mi.load_dict({
        "type": "spot", "cutoff_angle": 30.0, "beam_width": 20.0,
        "intensity": {"type": "rgb", "value": [2.0, 3.0, 4.0]},
        "texture": {"type": "bitmap", "bitmap": mi.Bitmap(texels()), "raw": True,
                    "filter_type": "bilinear", "wrap_mode": "repeat"},
        "to_world": to_world,
    })
    print(f"// Mitsuba {mi.__version__}, scalar_rgb: world point, radiance received from the spot")
    rng = np.random.default_rng(7)
    rows = 0
    while rows < 24:
        # Directions in the light's frame spread over the cone (and a little beyond it).
        theta = math.radians(rng.uniform(0.0, 32.0))
        phi = rng.uniform(0.0, 2.0 * math.pi)
        dist = rng.uniform(0.5, 3.0)
        local = [math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta)]
        p = to_world @ mi.ScalarPoint3f(*[dist * c for c in local])
        it = mi.Interaction3f()
        it.p = mi.Point3f(p)
        _, value = spot.sample_direction(it, mi.Point2f(0.5, 0.5))
        print(f"  {{{{{p[0]!r}f, {p[1]!r}f, {p[2]!r}f}}, "
              f"{{{value[0]!r}f, {value[1]!r}f, {value[2]!r}f}}}},")
        rows += 1


if __name__ == "__main__":
    main()
