#!/usr/bin/env python3
"""Where the texture-coordinate rules of Tessera's mesh readers come from (docs/scenes.md,
"Texture coordinates"): writes one small OBJ, PLY (under each of Mitsuba's uv property names)
and serialized file, loads each with Mitsuba 3 (scalar_rgb) and prints the uvs Mitsuba keeps,
and which image row a bitmap lookup at v = 0.25 reads.

    /path/to/venv-with-mitsuba/bin/python core/scene/mesh/mitsuba_uv_reference.py

Output with Mitsuba 3.x (the numbers obj_loader_test, ply_loader_test and
serialized_loader_test expect):
    obj vt (0.1, 0.2) -> (0.1, 0.8)
    ply u/v (0.1, 0.2) -> (0.1, 0.2)
    ply s/t (0.1, 0.2) -> (0.1, 0.2)
    ply texture_u/texture_v (0.1, 0.2) -> (0.1, 0.2)
    serialized (0.1, 0.2) -> (0.1, 0.2)
    bitmap at v=0.25 reads the top row
that is: OBJ flips v, PLY and serialized keep it, and v runs down the image.
"""
import os
import struct
import tempfile
import zlib

import numpy as np
import mitsuba as mi

mi.set_variant("scalar_rgb")


def uvs(kind, path):
    mesh = mi.load_dict({"type": kind, "filename": path})
    return np.array(mesh.vertex_texcoords_buffer()).reshape(-1, 2)[0]


def main():
    d = tempfile.mkdtemp()
    obj = os.path.join(d, "t.obj")
    with open(obj, "w") as f:
        f.write("v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0.1 0.2\nvt 0.3 0.4\nvt 0.5 0.6\nf 1/1 2/2 3/3\n")
    print("obj vt (0.1, 0.2) ->", tuple(round(float(x), 6) for x in uvs("obj", obj)))
    for u, v in [("u", "v"), ("s", "t"), ("texture_u", "texture_v")]:
        ply = os.path.join(d, f"t_{u}.ply")
        with open(ply, "w") as f:
            f.write("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                    f"property float z\nproperty float {u}\nproperty float {v}\nelement face 1\n"
                    "property list uchar int vertex_indices\nend_header\n"
                    "0 0 0 0.1 0.2\n1 0 0 0.3 0.4\n1 1 0 0.5 0.6\n3 0 1 2\n")
        print(f"ply {u}/{v} (0.1, 0.2) ->", tuple(round(float(x), 6) for x in uvs("ply", ply)))
    body = struct.pack("<I", 0x1002) + b"t\0" + struct.pack("<QQ", 3, 1)
    body += struct.pack("<9f", 0, 0, 0, 1, 0, 0, 1, 1, 0)
    body += struct.pack("<6f", 0.1, 0.2, 0.3, 0.4, 0.5, 0.6) + struct.pack("<3I", 0, 1, 2)
    ser = os.path.join(d, "t.serialized")
    with open(ser, "wb") as f:
        f.write(struct.pack("<HH", 0x041C, 4) + zlib.compress(body) + struct.pack("<QI", 0, 1))
    print("serialized (0.1, 0.2) ->", tuple(round(float(x), 6) for x in uvs("serialized", ser)))
    image = np.zeros((2, 1, 3), dtype=np.float32)
    image[0, 0] = [1, 0, 0]  # top row red, bottom row blue
    image[1, 0] = [0, 0, 1]
    exr = os.path.join(d, "tb.exr")
    mi.Bitmap(image).write(exr)
    texture = mi.load_dict({"type": "bitmap", "filename": exr, "filter_type": "nearest"})
    si = mi.SurfaceInteraction3f()
    si.uv = mi.Point2f(0.5, 0.25)
    row = "top" if texture.eval(si)[0] > 0.5 else "bottom"
    print(f"bitmap at v=0.25 reads the {row} row")


if __name__ == "__main__":
    main()
