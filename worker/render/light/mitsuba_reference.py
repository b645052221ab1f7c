"""Reference values for worker/render/light/*_test.cpp from Mitsuba 3 (scalar_rgb).

Run with a Python that has mitsuba installed:  python worker/render/light/mitsuba_reference.py
It prints the C++ tables pasted into the tests (envmap_light_test.cpp, spot_light_test.cpp).
"""
import math

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")


def spot_falloff():
    # Spot at the origin shining along +z; a point at distance 1 at angle theta from the axis
    # receives intensity * falloff / 1^2.
    spot = mi.load_dict({"type": "spot", "cutoff_angle": 30.0, "beam_width": 20.0,
                         "intensity": {"type": "rgb", "value": [1.0, 1.0, 1.0]}})
    rows = []
    for theta_deg in [0.0, 10.0, 19.9, 20.5, 22.0, 25.0, 28.0, 29.9, 30.5, 45.0, 120.0]:
        t = math.radians(theta_deg)
        it = mi.Interaction3f()
        it.p = mi.Point3f(math.sin(t), 0.0, math.cos(t))
        ds, value = spot.sample_direction(it, mi.Point2f(0.5, 0.5))
        rows.append((theta_deg, value[0]))
    print("// theta_deg, Mitsuba's received radiance at distance 1 (intensity 1)")
    for theta, v in rows:
        print(f"  {{{theta!r}f, {v!r}f}},")


def envmap_values():
    # A 4 x 3 map with distinct texels, rotated by to_world (90 degrees about x, then 30 about y).
    h, w = 3, 4
    data = np.zeros((h, w, 3), dtype=np.float32)
    for y in range(h):
        for x in range(w):
            data[y, x] = [1 + x + 4 * y, 0.5 * (x + 1), 0.25 * (y + 1)]
    to_world = mi.ScalarTransform4f().rotate([0, 1, 0], 30.0) @ mi.ScalarTransform4f().rotate([1, 0, 0], 90.0)
    env = mi.load_dict({"type": "envmap", "bitmap": mi.Bitmap(data), "scale": 2.0,
                        "to_world": to_world})
    dirs = [(0.3, 0.5, -0.8), (-0.7, 0.1, 0.2), (0.0, -1.0, 0.0), (0.05, 0.99, 0.1),
            (1.0, 0.0, 0.0), (-0.2, -0.3, -0.9), (0.6, -0.6, 0.5)]
    print("// direction (unnormalised), Mitsuba's radiance arriving from it")
    for d in dirs:
        n = math.sqrt(sum(c * c for c in d))
        dn = [c / n for c in d]
        si = mi.SurfaceInteraction3f()
        si.wi = mi.Vector3f(-dn[0], -dn[1], -dn[2])
        v = env.eval(si)
        print(f"  {{{{{d[0]}f, {d[1]}f, {d[2]}f}}, {{{v[0]!r}f, {v[1]!r}f, {v[2]!r}f}}}},")


spot_falloff()
envmap_values()
