#!/usr/bin/env python3
"""Check which way the faces of an OBJ file face, group by group.

For each group (usemtl) it counts faces whose winding normal, cross(v1 - v0, v2 - v0), points
  - "out": away from the group's own centroid (right for closed objects: spheres, boxes),
  - "in":  towards the group's centroid,
and, against the whole model's centroid ("towards model centre": right for room walls, a ceiling
light facing down), plus whether the winding agrees with the file's vertex normals (vn), if any.
Planar groups (walls, lights) have no meaningful own-centroid test; the model-centre test applies.

Usage: python3 bench/check_obj_winding.py FILE.obj [--center X Y Z]
Standard library only.
"""
import argparse
import math
import sys


def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def dot(a, b):
    return sum(a[i] * b[i] for i in range(3))


def read(path):
    v, vn, groups, cur = [], [], {}, "(none)"
    for line in open(path, errors="replace"):
        w = line.split()
        if not w:
            continue
        if w[0] == "v":
            v.append([float(x) for x in w[1:4]])
        elif w[0] == "vn":
            vn.append([float(x) for x in w[1:4]])
        elif w[0] == "usemtl":
            cur = w[1]
        elif w[0] == "f":
            cs = []
            for c in w[1:]:
                p = c.split("/")
                vi = int(p[0])
                ni = int(p[2]) if len(p) > 2 and p[2] else None
                cs.append((vi - 1 if vi > 0 else len(v) + vi,
                           None if ni is None else (ni - 1 if ni > 0 else len(vn) + ni)))
            g = groups.setdefault(cur, [])
            for k in range(1, len(cs) - 1):
                g.append((cs[0], cs[k], cs[k + 1]))
    return v, vn, groups


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("obj")
    ap.add_argument("--center", type=float, nargs=3, help="model centre (default: bounding-box centre)")
    args = ap.parse_args()
    v, vn, groups = read(args.obj)
    lo = [min(p[i] for p in v) for i in range(3)]
    hi = [max(p[i] for p in v) for i in range(3)]
    centre = args.center or [(lo[i] + hi[i]) / 2 for i in range(3)]
    print(f"{args.obj}: {len(v)} vertices, {len(vn)} normals, bounds {lo} .. {hi}, "
          f"model centre {centre}")
    print(f"{'group':14s} {'tris':>5s} {'out(own)':>9s} {'in(own)':>8s} {'to-centre':>10s} "
          f"{'away':>5s} {'vn-agree':>9s} {'vn-disagree':>12s}  mean normal")
    for name, tris in groups.items():
        pts = [v[c[0]] for t in tris for c in t]
        gc = [sum(p[i] for p in pts) / len(pts) for i in range(3)]
        out = inn = toc = away = agree = dis = 0
        mean_n = [0.0, 0.0, 0.0]
        for t in tris:
            a, b, c = (v[k[0]] for k in t)
            n = cross(sub(b, a), sub(c, a))
            ln = math.sqrt(dot(n, n))
            if ln == 0:
                continue
            n = [x / ln for x in n]
            mean_n = [mean_n[i] + n[i] for i in range(3)]
            fc = [(a[i] + b[i] + c[i]) / 3 for i in range(3)]
            d_own = dot(n, sub(fc, gc))
            out += d_own > 1e-9
            inn += d_own < -1e-9
            d_c = dot(n, sub(centre, fc))
            toc += d_c > 0
            away += d_c < 0
            if all(k[1] is not None for k in t):
                nv = [sum(vn[k[1]][i] for k in t) for i in range(3)]
                if dot(nv, n) > 0:
                    agree += 1
                else:
                    dis += 1
        ln = math.sqrt(dot(mean_n, mean_n)) or 1
        print(f"{name:14s} {len(tris):5d} {out:9d} {inn:8d} {toc:10d} {away:5d} {agree:9d} {dis:12d}  "
              f"[{', '.join(f'{x / ln:+.3f}' for x in mean_n)}]")
    return 0


if __name__ == "__main__":
    sys.exit(main())
