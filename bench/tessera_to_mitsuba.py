#!/usr/bin/env python3
"""Render a Tessera scene file (format v1, docs/scenes.md) with Mitsuba 3.

A second opinion on the example scenes: it shows whether a scene is what it should be (windings,
light placement, exposure) independently of Tessera's own parser and renderer, and gives a Mitsuba
figure on scenes other than the Cornell box. It converts to a Mitsuba scene:
  quad -> two triangles (v0 v1 v2) (v0 v2 v3); tetrahedron -> four outward triangles; box -> twelve
  triangles (outward, inward with flip_normals); sphere -> Mitsuba's exact sphere; triangles;
  mesh -> PLY (read here) or OBJ (read here, MTL: Kd diffuse, Ke emission, illum 5 mirror,
  illum 7 glass with Ni; everything else ignored); transforms scale -> rotate -> translate;
  diffuse -> diffuse, mirror -> conductor "none" (reflectance 1), glass -> dielectric (int_ior);
  "two_sided" -> twosided BSDF / emission on both sides is NOT supported by Mitsuba's area emitter
  (refused); emission -> area emitter radiance; power -> radiance = power / (pi * area).
Surfaces are one-sided as in Tessera; Mitsuba's front is the counter-clockwise side, like Tessera's.

Usage: .venv-bench/bin/python bench/tessera_to_mitsuba.py SCENE.json -o OUT.exr [--png OUT.png]
           [--spp N] [--max-depth D] [--width W --height H] [--threads T] [--seed S]
The PNG is sRGB, clamped (exposure 1). Mesh files are written to a temporary folder as PLY.
"""
import argparse
import json
import math
import struct
import sys
import tempfile
import time
from pathlib import Path

import numpy as np


# ---------------------------------------------------------------- transforms
def rotation_matrix(axis, angle_deg):
    a = np.asarray(axis, dtype=np.float64)
    a = a / np.linalg.norm(a)
    c, s = math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg))
    x, y, z = a
    return np.array([[c + x * x * (1 - c), x * y * (1 - c) - z * s, x * z * (1 - c) + y * s],
                     [y * x * (1 - c) + z * s, c + y * y * (1 - c), y * z * (1 - c) - x * s],
                     [z * x * (1 - c) - y * s, z * y * (1 - c) + x * s, c + z * z * (1 - c)]])


def transform_matrix(t):
    """4x4 matrix of a Tessera transform object or array of them (applied in order)."""
    if t is None:
        return np.eye(4)
    if isinstance(t, list):
        m = np.eye(4)
        for step in t:
            m = transform_matrix(step) @ m
        return m
    m = np.eye(4)
    if "scale" in t:
        s = t["scale"]
        s = [s, s, s] if isinstance(s, (int, float)) else s
        m = np.diag([s[0], s[1], s[2], 1.0]) @ m
    if "rotate" in t:
        r = np.eye(4)
        r[:3, :3] = rotation_matrix(t["rotate"]["axis"], t["rotate"]["angle"])
        m = r @ m
    if "translate" in t:
        tr = np.eye(4)
        tr[:3, 3] = t["translate"]
        m = tr @ m
    return m


def apply(m, pts):
    pts = np.asarray(pts, dtype=np.float64)
    return pts @ m[:3, :3].T + m[:3, 3]


def apply_normals(m, nrm):
    n = np.asarray(nrm, dtype=np.float64) @ np.linalg.inv(m[:3, :3])
    return n / np.linalg.norm(n, axis=1, keepdims=True)


# ---------------------------------------------------------------- mesh files
def read_ply(path):
    """Binary little endian or ASCII PLY: float x y z [nx ny nz], faces as list of int indices."""
    data = Path(path).read_bytes()
    end = data.index(b"end_header") + len(b"end_header")
    end = data.index(b"\n", end) + 1
    header = data[:end].decode("ascii").splitlines()
    fmt = next(l.split()[1] for l in header if l.startswith("format"))
    elements, cur = [], None
    for l in header:
        w = l.split()
        if w[0] == "element":
            cur = {"name": w[1], "count": int(w[2]), "props": []}
            elements.append(cur)
        elif w[0] == "property":
            cur["props"].append(w[1:])
    types = {"char": "b", "int8": "b", "uchar": "B", "uint8": "B", "short": "h", "int16": "h",
             "ushort": "H", "uint16": "H", "int": "i", "int32": "i", "uint": "I", "uint32": "I",
             "float": "f", "float32": "f", "double": "d", "float64": "d"}
    body = data[end:]
    verts, normals, faces = [], [], []
    if fmt == "ascii":
        tokens = iter(body.split())
        rd = lambda t: float(next(tokens)) if types[t] in "fd" else int(next(tokens))
    else:
        assert fmt == "binary_little_endian", fmt
        off = [0]

        def rd(t):
            c = "<" + types[t]
            v = struct.unpack_from(c, body, off[0])[0]
            off[0] += struct.calcsize(c)
            return v
    for el in elements:
        for _ in range(el["count"]):
            rec = {}
            for p in el["props"]:
                if p[0] == "list":
                    n = rd(p[1])
                    rec[p[3]] = [rd(p[2]) for _ in range(n)]
                else:
                    rec[p[1]] = rd(p[0])
            if el["name"] == "vertex":
                verts.append([rec["x"], rec["y"], rec["z"]])
                if "nx" in rec:
                    normals.append([rec["nx"], rec["ny"], rec["nz"]])
            elif el["name"] == "face":
                idx = rec.get("vertex_indices", rec.get("vertex_index"))
                for k in range(1, len(idx) - 1):
                    faces.append([idx[0], idx[k], idx[k + 1]])
    return np.array(verts), (np.array(normals) if normals else None), np.array(faces, dtype=np.int64)


def read_mtl(path):
    mats, cur = {}, None
    for line in Path(path).read_text(errors="replace").splitlines():
        w = line.split()
        if not w:
            continue
        if w[0] == "newmtl":
            cur = mats.setdefault(w[1], {"Kd": [0.8, 0.8, 0.8], "Ke": [0, 0, 0], "illum": 2, "Ni": 1.5})
        elif cur is not None and w[0] in ("Kd", "Ke") and len(w) >= 4:
            cur[w[0]] = [float(x) for x in w[1:4]]
        elif cur is not None and w[0] == "illum":
            cur["illum"] = int(w[1])
        elif cur is not None and w[0] == "Ni":
            cur["Ni"] = float(w[1])
    return mats


def read_obj(path):
    """Returns ({material name: (positions, normals or None, faces)}, mtl dict). Per-corner data
    is expanded (no shared vertices), so each group is a plain triangle soup."""
    v, vn = [], []
    groups, mtl, cur = {}, {}, "(none)"
    base = Path(path).parent
    for line in Path(path).read_text(errors="replace").splitlines():
        w = line.split()
        if not w:
            continue
        if w[0] == "v":
            v.append([float(x) for x in w[1:4]])
        elif w[0] == "vn":
            vn.append([float(x) for x in w[1:4]])
        elif w[0] == "usemtl":
            cur = w[1]
        elif w[0] == "mtllib":
            mtl.update(read_mtl(base / " ".join(w[1:])))
        elif w[0] == "f":
            corners = []
            for c in w[1:]:
                parts = c.split("/")
                vi = int(parts[0])
                vi = vi - 1 if vi > 0 else len(v) + vi
                ni = None
                if len(parts) > 2 and parts[2]:
                    ni = int(parts[2])
                    ni = ni - 1 if ni > 0 else len(vn) + ni
                corners.append((vi, ni))
            g = groups.setdefault(cur, [])
            for k in range(1, len(corners) - 1):
                g.append((corners[0], corners[k], corners[k + 1]))
    out = {}
    for name, tris in groups.items():
        pos = np.array([v[c[0]] for t in tris for c in t])
        has_n = all(c[1] is not None for t in tris for c in t)
        nrm = np.array([vn[c[1]] for t in tris for c in t]) if has_n else None
        faces = np.arange(len(pos)).reshape(-1, 3)
        out[name] = (pos, nrm, faces)
    return out, mtl


def write_ply(path, pos, faces, normals=None):
    pos = np.asarray(pos, dtype="<f4")
    faces = np.asarray(faces, dtype="<i4")
    head = ["ply", "format binary_little_endian 1.0", f"element vertex {len(pos)}",
            "property float x", "property float y", "property float z"]
    if normals is not None:
        head += ["property float nx", "property float ny", "property float nz"]
    head += [f"element face {len(faces)}", "property list uchar int vertex_indices", "end_header"]
    vert = pos if normals is None else np.hstack([pos, np.asarray(normals, dtype="<f4")])
    rec = np.zeros(len(faces), dtype=[("n", "u1"), ("i", "<i4", (3,))])
    rec["n"] = 3
    rec["i"] = faces
    with open(path, "wb") as f:
        f.write(("\n".join(head) + "\n").encode())
        f.write(np.ascontiguousarray(vert, dtype="<f4").tobytes())
        f.write(rec.tobytes())


def tri_area(pos, faces):
    p = np.asarray(pos)[np.asarray(faces)]
    return float(0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1).sum())


# ---------------------------------------------------------------- conversion
def bsdf_dict(m, two_sided=False):
    t = m.get("type", "diffuse")
    if t == "diffuse":
        b = {"type": "diffuse", "reflectance": {"type": "rgb", "value": m.get("reflectance", [0.5] * 3)}}
    elif t == "mirror":
        b = {"type": "conductor", "material": "none"}
    elif t == "glass":
        return {"type": "dielectric", "int_ior": float(m.get("ior", 1.5)), "ext_ior": 1.0}
    else:
        raise ValueError(f"material type {t}")
    if two_sided or m.get("two_sided", False):
        b = {"type": "twosided", "bsdf": b}
    return b


def convert(scene, scene_dir, tmp, args):
    import mitsuba as mi
    cam = scene["camera"]
    film = scene.get("film", {})
    render = scene.get("render", {})
    width = args.width or film.get("width", 256)
    height = args.height or film.get("height", 256)
    max_depth = args.max_depth if args.max_depth is not None else render.get("max_depth", -1)
    d = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": int(max_depth)},
        "sensor": {
            "type": "perspective",
            "fov": float(cam.get("fov", 39.3)),
            "fov_axis": cam.get("fov_axis", "x"),
            "to_world": mi.ScalarTransform4f().look_at(origin=cam["position"], target=cam["look_at"],
                                                       up=cam.get("up", [0, 1, 0])),
            "film": {"type": "hdrfilm", "width": int(width), "height": int(height),
                     "rfilter": {"type": "box"}, "pixel_format": "rgb"},
            "sampler": {"type": "independent", "sample_count": int(args.spp or render.get("spp", 64))},
        },
    }
    mats = scene.get("materials", {})
    counter = [0]
    total_power = [0.0]

    def add_tris(pos, faces, shape, bsdf, normals=None, area_for_power=None):
        counter[0] += 1
        path = Path(tmp) / f"shape{counter[0]}.ply"
        write_ply(path, pos, faces, normals)
        e = {"type": "ply", "filename": str(path), "bsdf": bsdf, "face_normals": normals is None}
        if shape.get("flip_normals"):
            e["flip_normals"] = True
        add_emitter(e, shape, area_for_power if area_for_power is not None else tri_area(pos, faces))
        d[f"shape{counter[0]}"] = e

    def add_emitter(e, shape, area):
        two = shape.get("two_sided", False)
        if "emission" in shape or "power" in shape:
            if two:
                raise SystemExit("two-sided emitters are not supported by this converter")
            if "emission" in shape:
                rad = shape["emission"]
            else:
                p = shape["power"]
                p = [p, p, p] if isinstance(p, (int, float)) else p
                rad = [x / (math.pi * area) for x in p]
                total_power[0] += sum(p) / 3
            rad = [rad] * 3 if isinstance(rad, (int, float)) else rad
            e["emitter"] = {"type": "area", "radiance": {"type": "rgb", "value": [float(x) for x in rad]}}

    def mat_of(shape):
        name = shape.get("material")
        return bsdf_dict(mats[name], shape.get("two_sided", False))

    for i, s in enumerate(scene["shapes"]):
        t = s["type"]
        m = transform_matrix(s.get("transform"))
        if t == "quad":
            pos = apply(m, s["vertices"])
            add_tris(pos, [[0, 1, 2], [0, 2, 3]], s, mat_of(s))
        elif t == "triangles":
            pos = apply(m, s["vertices"])
            add_tris(pos, s["indices"], s, mat_of(s))
        elif t == "tetrahedron":
            p = apply(m, s["vertices"])
            c = p.mean(axis=0)
            faces = []
            for f in ([0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]):
                a, b, cc = p[f]
                n = np.cross(b - a, cc - a)
                faces.append(f if np.dot(n, a - c) > 0 else [f[0], f[2], f[1]])
            pos = np.concatenate([p[f] for f in faces])  # unshared corners: flat shading
            add_tris(pos, np.arange(12).reshape(4, 3), s, mat_of(s))
        elif t == "box":
            lo, hi = np.array(s["min"], float), np.array(s["max"], float)
            corners = np.array([[hi[0] if k & 1 else lo[0], hi[1] if k & 2 else lo[1],
                                 hi[2] if k & 4 else lo[2]] for k in range(8)])
            quads = [[0, 2, 6, 4], [1, 5, 7, 3], [0, 4, 5, 1], [2, 3, 7, 6], [0, 1, 3, 2], [4, 6, 7, 5]]
            p = apply(m, corners)
            c = p.mean(axis=0)
            pos, faces = [], []
            for q in quads:
                a, b, cc = p[q[0]], p[q[1]], p[q[2]]
                if np.dot(np.cross(b - a, cc - a), a - c) < 0:
                    q = q[::-1]
                base = len(pos)
                pos += [p[k] for k in q]
                faces += [[base, base + 1, base + 2], [base, base + 2, base + 3]]
            add_tris(np.array(pos), faces, s, mat_of(s))  # flip_normals handled by Mitsuba
        elif t == "sphere":
            c = apply(m, [s["center"]])[0]
            scale = abs(np.linalg.det(m[:3, :3])) ** (1 / 3)
            r = s["radius"] * scale
            e = {"type": "sphere", "center": [float(x) for x in c], "radius": float(r), "bsdf": mat_of(s)}
            if s.get("flip_normals"):
                e["flip_normals"] = True
            add_emitter(e, s, 4 * math.pi * r * r)
            counter[0] += 1
            d[f"shape{counter[0]}"] = e
        elif t == "mesh":
            f = scene_dir / s["file"]
            if f.suffix.lower() == ".ply":
                pos, nrm, faces = read_ply(f)
                pos = apply(m, pos)
                nrm = apply_normals(m, nrm) if nrm is not None else None
                add_tris(pos, faces, s, mat_of(s), nrm)
            elif f.suffix.lower() == ".obj":
                groups, mtl = read_obj(f)
                for name, (pos, nrm, faces) in groups.items():
                    pos = apply(m, pos)
                    nrm = apply_normals(m, nrm) if nrm is not None else None
                    sub = dict(s)
                    if "material" in s:
                        bsdf = mat_of(s)
                    else:
                        mm = mtl.get(name, {"Kd": [0.8] * 3, "Ke": [0, 0, 0], "illum": 2})
                        if mm["illum"] == 5:
                            tm = {"type": "mirror"}
                        elif mm["illum"] == 7:
                            tm = {"type": "glass", "ior": mm.get("Ni", 1.5)}
                        else:
                            tm = {"type": "diffuse", "reflectance": mm["Kd"]}
                        bsdf = bsdf_dict(tm, s.get("two_sided", False))
                        if any(x > 0 for x in mm["Ke"]) and "emission" not in s and "power" not in s:
                            sub["emission"] = mm["Ke"]
                    add_tris(pos, faces, sub, bsdf, nrm)
            else:
                raise SystemExit(f"shapes[{i}]: unsupported mesh file {f}")
        else:
            raise SystemExit(f"shapes[{i}]: unsupported type {t}")
    return d


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene")
    ap.add_argument("-o", "--out", required=True, help="EXR output")
    ap.add_argument("--png", help="also write an sRGB PNG")
    ap.add_argument("--spp", type=int)
    ap.add_argument("--max-depth", type=int)
    ap.add_argument("--width", type=int)
    ap.add_argument("--height", type=int)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--variant", default="llvm_ad_rgb")
    args = ap.parse_args()

    import drjit as dr
    import mitsuba as mi
    mi.set_variant(args.variant)
    dr.set_thread_count(args.threads)
    scene_path = Path(args.scene)
    scene_json = json.loads(scene_path.read_text())
    with tempfile.TemporaryDirectory() as tmp:
        d = convert(scene_json, scene_path.parent, tmp, args)
        t0 = time.perf_counter()
        sc = mi.load_dict(d)
        t_load = time.perf_counter() - t0
    t0 = time.perf_counter()
    img = mi.render(sc, seed=args.seed)
    arr = np.array(img, dtype=np.float32)
    dt = time.perf_counter() - t0
    film = sc.sensors()[0].film()
    w, h = film.crop_size()
    spp = sc.sensors()[0].sampler().sample_count()
    print(f"{scene_path}: {w}x{h}, {spp} spp, load {t_load:.2f} s, render {dt:.2f} s "
          f"(incl. JIT), mean RGB {arr.reshape(-1, 3).mean(axis=0)}, "
          f"non-finite {np.count_nonzero(~np.isfinite(arr))}")
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    bmp = mi.Bitmap(arr, pixel_format=mi.Bitmap.PixelFormat.RGB)
    bmp.write(args.out)
    if args.png:
        bmp.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.UInt8, srgb_gamma=True).write(args.png)
    return 0


if __name__ == "__main__":
    sys.exit(main())
