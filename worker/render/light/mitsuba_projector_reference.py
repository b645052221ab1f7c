"""Reference values for the projector light (projector_light_test.cpp) from Mitsuba 3.

Run with a Python that has mitsuba installed (scalar_rgb variant):
    python worker/render/light/mitsuba_projector_reference.py \
        > worker/render/light/mitsuba_projector_reference.inc
It prints C++ table rows: a point (x, y, z) in world space and the radiance Mitsuba's projector
sends to it (sample_direction's value). Two projectors: "textured" stands at (1, 2, 3), rotated,
fov 40 (along x), scale 1.5, with a 4 x 3 linear float irradiance texture (texel (x, y) =
(1 + x + 4 y, 0.5 (x + 1), 0.25 (y + 1)), bilinear, repeat), so the image is 4:3; "constant" has
irradiance (0.5, 1, 2), fov 60 and the default frame. Points spread over each frustum and a
little beyond it (those receive 0).
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


def rows(name, projector, to_world, tan_x, tan_y, rng, count):
    print(f"// {name}: world point, radiance received")
    for _ in range(count):
        # A point in the projector's frame: z in [0.5, 3], x and y up to 1.1 x the frustum.
        z = rng.uniform(0.5, 3.0)
        x = rng.uniform(-1.1, 1.1) * tan_x * z
        y = rng.uniform(-1.1, 1.1) * tan_y * z
        p = to_world @ mi.ScalarPoint3f(x, y, z)
        it = mi.Interaction3f()
        it.p = mi.Point3f(p)
        _, value = projector.sample_direction(it, mi.Point2f(0.5, 0.5))
        print(f"  {{{{{p[0]!r}f, {p[1]!r}f, {p[2]!r}f}}, "
              f"{{{value[0]!r}f, {value[1]!r}f, {value[2]!r}f}}}},")


def main():
    print(f"// Mitsuba {mi.__version__}, scalar_rgb")
    rng = np.random.default_rng(11)
    to_world = (mi.ScalarTransform4f().translate([1.0, 2.0, 3.0])
                @ mi.ScalarTransform4f().rotate([0, 1, 0], 30.0)
                @ mi.ScalarTransform4f().rotate([1, 0, 0], -50.0))
    textured = mi.load_dict({
        "type": "projector", "fov": 40.0, "scale": 1.5, "to_world": to_world,
        "irradiance": {"type": "bitmap", "bitmap": mi.Bitmap(texels()), "raw": True,
                       "filter_type": "bilinear", "wrap_mode": "repeat"},
    })
    tan_x = math.tan(math.radians(20.0))
    print("#ifdef TEXTURED_PROJECTOR")
    rows("textured", textured, to_world, tan_x, tan_x * H / W, rng, 24)
    print("#else")
    constant = mi.load_dict({"type": "projector", "fov": 60.0,
                             "irradiance": {"type": "rgb", "value": [0.5, 1.0, 2.0]}})
    tan_x = math.tan(math.radians(30.0))
    rows("constant", constant, mi.ScalarTransform4f(), tan_x, tan_x, rng, 12)
    print("#endif")


if __name__ == "__main__":
    main()
