"""Reference values for the spot light with an 8-bit sRGB grey texture (spot_light_test.cpp)
from Mitsuba 3: the kind of texture and frame of Mitsuba's docs/scenes/emitter_spot_texture.xml
(a grey JPEG, noise_01.jpg; lookat from (0, 0, 5) to the origin with up = -x).

Run with a Python that has mitsuba installed (scalar_rgb variant):
    python worker/render/light/mitsuba_spot_srgb_reference.py \
        > worker/render/light/mitsuba_spot_srgb_reference.inc
The texture is 7 x 5 grey 8-bit codes (x, y) -> (37 x + 91 y + 11) mod 256, sRGB-encoded
(Mitsuba decodes each texel, then interpolates). It prints C++ table rows: a point on the plane
z = 0 and the radiance Mitsuba's spot (intensity 200, cutoff_angle 20, default beam_width)
sends to it (sample_direction's value, red channel; grey, so all three agree).
"""
import os
import tempfile

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")

W, H = 7, 5


def codes():
    return np.array([[(37 * x + 91 * y + 11) % 256 for x in range(W)] for y in range(H)],
                    dtype=np.uint8).reshape(H, W, 1)


def main():
    folder = tempfile.mkdtemp()
    path = os.path.join(folder, "grey.png")
    mi.Bitmap(codes(), pixel_format=mi.Bitmap.PixelFormat.Y).write(path)
    spot = mi.load_dict({
        "type": "spot", "cutoff_angle": 20.0,
        "intensity": {"type": "rgb", "value": [200.0, 200.0, 200.0]},
        "texture": {"type": "bitmap", "filename": path},
        "to_world": mi.ScalarTransform4f().look_at(origin=[0, 0, 5], target=[0, 0, 0],
                                                   up=[-1, 0, 0]),
    })
    print(f"// Mitsuba {mi.__version__}, scalar_rgb: point on z = 0, radiance received (red)")
    rng = np.random.default_rng(5)
    for _ in range(48):
        x, y = (float(np.float32(c)) for c in rng.uniform(-1.9, 1.9, 2))
        it = mi.Interaction3f()
        it.p = mi.Point3f(x, y, 0.0)
        _, value = spot.sample_direction(it, mi.Point2f(0.5, 0.5))
        print(f"  {{{{{x!r}f, {y!r}f, 0.0f}}, {value[0]!r}f}},")


if __name__ == "__main__":
    main()
