#!/usr/bin/env python3
"""Generate scenes/cornell.json from the Mitsuba reference's resolved.json.

The Tessera Cornell box must be *exactly* the scene of tests/data/reference/cbox/resolved.json
(Mitsuba 3.9.1 mi.cornell_box(), transforms resolved to world space), so this script copies
camera, quads (same order, same vertex order = same winding), materials and the light's radiance
from it, and checks on the way that each quad's counter-clockwise winding gives the normal that
resolved.json lists: normal = normalize(cross(v1 - v0, v2 - v0)).

Usage: python3 bench/make_cornell_json.py [--resolved PATH] [--out PATH] [--check]
  --check  only verify that the existing output equals what would be generated (exit 1 if not).
Standard library only.
"""
import argparse
import json
import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_RESOLVED = ROOT / "tests/data/reference/cbox/resolved.json"
DEFAULT_OUT = ROOT / "scenes/cornell.json"


def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def normalize(a):
    n = math.sqrt(sum(x * x for x in a))
    return [x / n for x in a]


def dot(a, b):
    return sum(a[i] * b[i] for i in range(3))


def winding_normal(v):
    return normalize(cross(sub(v[1], v[0]), sub(v[2], v[0])))


def check_quad(q):
    """Returns a list of problems with quad q (empty = fine)."""
    v = q["vertices"]
    problems = []
    if len(v) != 4:
        return [f"{q['name']}: {len(v)} vertices"]
    n = winding_normal(v)
    # Both triangles (v0 v1 v2) and (v0 v2 v3) must agree, and the quad must be planar.
    n2 = normalize(cross(sub(v[2], v[0]), sub(v[3], v[0])))
    if dot(n, n2) < 1 - 1e-6:
        problems.append(f"{q['name']}: not planar/convex (triangle normals {n} vs {n2})")
    listed = q["normal"]
    d = dot(n, listed)
    if d < 1 - 1e-6:
        problems.append(f"{q['name']}: winding normal {[round(x, 7) for x in n]} "
                        f"!= listed normal {listed} (dot {d:.7f})")
    return problems


def build(resolved):
    cam = resolved["camera"]
    w, h = resolved["resolution"]
    materials = {name: {"type": m["type"], "reflectance": m["reflectance"]}
                 for name, m in resolved["materials"].items()}
    light = resolved["light"]
    shapes = []
    for q in resolved["quads"]:
        if q["material"] not in materials:
            raise SystemExit(f"quad {q['name']}: unknown material {q['material']}")
        if q["reflectance"] != materials[q["material"]]["reflectance"]:
            raise SystemExit(f"quad {q['name']}: reflectance differs from material {q['material']}")
        s = {"type": "quad", "vertices": q["vertices"], "material": q["material"]}
        if "emitter" in q:
            e = q["emitter"]
            assert e["type"] == "area" and e["one_sided"] is True
            assert e["radiance"] == light["radiance"] and q["name"] == light["quad"]
            s["emission"] = e["radiance"]
        shapes.append(s)
    assert cam["fov_axis"] == "smaller"
    return {
        "tessera": 1,
        "camera": {
            "position": cam["origin"],
            "look_at": cam["target"],
            "up": cam["up"],
            "fov": cam["fov_deg"],
            "fov_axis": cam["fov_axis"],
        },
        "film": {"width": w, "height": h},
        "render": {"spp": 256},
        "materials": materials,
        "shapes": shapes,
    }


def dump(scene):
    """JSON with one line per vertex list, so the file stays readable and diffable."""
    text = json.dumps(scene, indent=2)
    # Collapse innermost numeric arrays ([x, y, z]) onto one line.
    import re
    text = re.sub(r"\[\s*(-?[\d.eE+-]+),\s*(-?[\d.eE+-]+),\s*(-?[\d.eE+-]+)\s*\]",
                  r"[\1, \2, \3]", text)
    return text + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--resolved", type=Path, default=DEFAULT_RESOLVED)
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT)
    ap.add_argument("--check", action="store_true")
    args = ap.parse_args()

    resolved = json.loads(args.resolved.read_text())
    problems = []
    for q in resolved["quads"]:
        problems += check_quad(q)
    n_quads = len(resolved["quads"])
    if problems:
        print(f"winding check: {len(problems)} problem(s) in {n_quads} quads:")
        for p in problems:
            print("  " + p)
    else:
        print(f"winding check: all {n_quads} quads: counter-clockwise winding gives the listed normal")

    text = dump(build(resolved))
    assert json.loads(text) == build(resolved)  # the pretty-printing changed nothing
    if args.check:
        same = args.out.exists() and args.out.read_text() == text
        print(f"{args.out}: {'up to date' if same else 'DIFFERS from generated'}")
        return 0 if same and not problems else 1
    args.out.write_text(text)
    print(f"wrote {args.out} ({len(resolved['quads'])} quads)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
