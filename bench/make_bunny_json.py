#!/usr/bin/env python3
"""Generate scenes/bunny.json: the Stanford bunny (scenes/meshes/bunny.ply) sitting on the floor
of the Cornell box room.

The room (floor, ceiling, back, red and green walls, the light) is the Cornell box of
tests/data/reference/cbox/resolved.json, copied with the same windings (walls face in, the light
faces down); the two boxes are left out. The bunny's transform comes from the PLY's bounds, read
here (binary little endian: float x y z, faces as uchar count + int indices): scaled so that it is
BUNNY_HEIGHT tall, turned about +y, centred in x-z and resting on the floor (y = -1).
Also checks the PLY's winding: the signed volume is positive when the faces face outward.

Usage: python3 bench/make_bunny_json.py [--out scenes/bunny.json] [--check]
Standard library only.
"""
import argparse
import json
import math
import re
import struct
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PLY = ROOT / "scenes/meshes/bunny.ply"
RESOLVED = ROOT / "tests/data/reference/cbox/resolved.json"
BUNNY_HEIGHT = 1.1
YAW_DEG = 20.0
FLOOR_Y = -1.0


def read_ply(path):
    data = path.read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").split("\n")
    assert "format binary_little_endian 1.0" in header, "expected binary little endian PLY"
    nv = int(next(l.split()[2] for l in header if l.startswith("element vertex")))
    nf = int(next(l.split()[2] for l in header if l.startswith("element face")))
    props = [l.split()[2] for l in header if l.startswith("property float")]
    assert props == ["x", "y", "z"], props
    assert "property list uchar int vertex_indices" in header
    verts = [struct.unpack_from("<3f", data, end + 12 * i) for i in range(nv)]
    off = end + 12 * nv
    faces = []
    for _ in range(nf):
        n = data[off]
        faces.append(struct.unpack_from(f"<{n}i", data, off + 1))
        off += 1 + 4 * n
    assert off == len(data), "trailing bytes after the faces"
    return verts, faces


def signed_volume(verts, faces):
    vol = 0.0
    for f in faces:
        a = verts[f[0]]
        for k in range(1, len(f) - 1):
            b, c = verts[f[k]], verts[f[k + 1]]
            vol += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                    + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6
    return vol


def build():
    verts, faces = read_ply(PLY)
    lo = [min(v[i] for v in verts) for i in range(3)]
    hi = [max(v[i] for v in verts) for i in range(3)]
    vol = signed_volume(verts, faces)
    s = BUNNY_HEIGHT / (hi[1] - lo[1])
    # after scaling, rotate about +y around the origin; centre the rotated footprint in x-z
    a = math.radians(YAW_DEG)
    rot = [(v[0] * s * math.cos(a) + v[2] * s * math.sin(a),
            -v[0] * s * math.sin(a) + v[2] * s * math.cos(a)) for v in verts]
    cx = (min(p[0] for p in rot) + max(p[0] for p in rot)) / 2
    cz = (min(p[1] for p in rot) + max(p[1] for p in rot)) / 2
    translate = [round(-cx, 6), round(FLOOR_Y - lo[1] * s, 6), round(-cz, 6)]
    info = {"vertices": len(verts), "faces": len(faces), "bounds": [lo, hi], "signed_volume": vol,
            "scale": s, "translate": translate}

    res = json.loads(RESOLVED.read_text())
    cam = res["camera"]
    room = []
    for q in res["quads"]:
        if q["shape"] != "rectangle":
            continue  # the two boxes
        sh = {"type": "quad", "vertices": q["vertices"], "material": q["material"]}
        if "emitter" in q:
            sh["emission"] = q["emitter"]["radiance"]
        room.append(sh)
    materials = {k: {"type": "diffuse", "reflectance": m["reflectance"]} for k, m in res["materials"].items()}
    materials["clay"] = {"type": "diffuse", "reflectance": [0.75, 0.62, 0.45]}
    scene = {
        "tessera": 1,
        "camera": {"position": cam["origin"], "look_at": cam["target"], "up": cam["up"],
                   "fov": cam["fov_deg"], "fov_axis": cam["fov_axis"]},
        "film": {"width": 512, "height": 512},
        "render": {"spp": 256},
        "materials": materials,
        "shapes": room + [{
            "type": "mesh",
            "file": "meshes/bunny.ply",
            "material": "clay",
            "transform": {"scale": round(s, 6), "rotate": {"axis": [0, 1, 0], "angle": YAW_DEG},
                          "translate": translate},
        }],
    }
    return scene, info


def dump(scene):
    text = json.dumps(scene, indent=2)
    num = r"(-?[\d.eE+-]+)"
    text = re.sub(r"\[\s*" + num + r",\s*" + num + r",\s*" + num + r"\s*\]", r"[\1, \2, \3]", text)
    return text + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, default=ROOT / "scenes/bunny.json")
    ap.add_argument("--check", action="store_true")
    args = ap.parse_args()
    scene, info = build()
    print(f"{PLY.name}: {info['vertices']} vertices, {info['faces']} faces, bounds {info['bounds']}, "
          f"signed volume {info['signed_volume']:.6g} ({'outward' if info['signed_volume'] > 0 else 'INWARD'}"
          f" winding); scale {info['scale']:.6f}, translate {info['translate']}")
    text = dump(scene)
    assert json.loads(text) == scene
    if args.check:
        same = args.out.exists() and args.out.read_text() == text
        print(f"{args.out}: {'up to date' if same else 'DIFFERS from generated'}")
        return 0 if same else 1
    args.out.write_text(text)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
