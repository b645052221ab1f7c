#!/usr/bin/env python3
"""Generate scenes/hexroom.json: the report's hexagonal room (report section 3.1 and 4).

Design (bench/README.md says why):
- a regular hexagon floor plan of circumradius R = 5 (flat walls at z = +-R*sin60 = +-4.33),
  floor at y = 0, roof at y = H = 4; six walls, floor and roof as one-sided quads facing into the
  room (floor and roof are each two trapezoids split along the x axis), so the room is closed;
- walls in distinct colours, the back wall (the one the camera faces, at -z) cyan;
- spheres resting on the floor: one mirror, one glass (ior 1.5), two diffuse;
- two regular tetrahedra standing on a face on the floor: one mirror, one diffuse;
- three 1x1 square lights 0.05 under the roof, facing down, given by their flux ("power");
- the camera at the back of the room (near the +z wall), offset to the right, looking across the
  room at the cyan wall, 55 degrees horizontal field of view, 1920x1080.
Every quad's winding is checked against the direction it must face.

Usage: python3 bench/make_hexroom_json.py [--out scenes/hexroom.json] [--check]
"""
import argparse
import json
import math
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
R = 5.0          # circumradius of the hexagon (= wall width)
H = 4.0          # floor-to-roof height
LIGHT_GAP = 0.05
LIGHT_SIZE = 1.0
LIGHT_POWER = 40.0   # watts per light, one-sided: radiance = P / (pi * area)
DIGITS = 6


def rnd(p):
    return [round(x + 0.0, DIGITS) + 0.0 for x in p]


def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def dot(a, b):
    return sum(a[i] * b[i] for i in range(3))


def normal(v):
    n = cross(sub(v[1], v[0]), sub(v[2], v[0]))
    length = math.sqrt(dot(n, n))
    return [x / length for x in n]


def oriented(verts, want):
    """Returns the quad's vertices ordered so that their CCW normal points along `want`."""
    verts = [rnd(p) for p in verts]
    if dot(normal(verts), want) < 0:
        verts = verts[::-1]
    n = normal(verts)
    assert dot(n, want) > (1 - 1e-6) * math.sqrt(dot(want, want)), (verts, want)
    # planarity: the second triangle agrees
    n2 = cross(sub(verts[2], verts[0]), sub(verts[3], verts[0]))
    assert dot(n, n2) > 0
    return verts


# Hexagon corners, counter-clockwise seen from above (+y): angle k*60 deg in the x-z plane.
# Corner 0 is (R, 0), corners 1,2 have z = -R*sin60 (the back wall, away from the camera)...
def corner(k):
    a = math.radians(60 * k)
    return [R * math.cos(a), 0.0, -R * math.sin(a)]


WALLS = [  # (corner i, corner i+1, material); named by where they stand seen from the camera
    (0, 1, "wall_red"),      # back right
    (1, 2, "wall_cyan"),     # back (faces the camera)
    (2, 3, "wall_green"),    # back left
    (3, 4, "wall_blue"),     # front left
    (4, 5, "wall_magenta"),  # front (behind the camera)
    (5, 0, "wall_yellow"),   # front right
]

MATERIALS = {
    "wall_red": {"type": "diffuse", "reflectance": [0.70, 0.12, 0.10]},
    "wall_cyan": {"type": "diffuse", "reflectance": [0.10, 0.55, 0.65]},
    "wall_green": {"type": "diffuse", "reflectance": [0.15, 0.55, 0.15]},
    "wall_blue": {"type": "diffuse", "reflectance": [0.15, 0.20, 0.65]},
    "wall_magenta": {"type": "diffuse", "reflectance": [0.60, 0.15, 0.55]},
    "wall_yellow": {"type": "diffuse", "reflectance": [0.75, 0.65, 0.15]},
    "floor": {"type": "diffuse", "reflectance": [0.65, 0.65, 0.65]},
    "roof": {"type": "diffuse", "reflectance": [0.75, 0.75, 0.75]},
    "light": {"type": "diffuse", "reflectance": [0.80, 0.80, 0.80]},
    "white": {"type": "diffuse", "reflectance": [0.75, 0.75, 0.75]},
    "orange": {"type": "diffuse", "reflectance": [0.75, 0.35, 0.08]},
    "mirror": {"type": "mirror"},
    "glass": {"type": "glass", "ior": 1.5},
}


def room():
    shapes = []
    centre = [0.0, H / 2, 0.0]
    c = [corner(k) for k in range(6)]
    for i, j, mat in WALLS:
        a, b = c[i], c[j]
        quad = [a, b, [b[0], H, b[2]], [a[0], H, a[2]]]
        mid = [(a[0] + b[0]) / 2, H / 2, (a[2] + b[2]) / 2]
        shapes.append({"type": "quad", "vertices": oriented(quad, sub(centre, mid)), "material": mat})
    # floor and roof: two trapezoids each, split along the x axis (corners 0 and 3)
    for y, want, mat in ((0.0, [0, 1, 0], "floor"), (H, [0, -1, 0], "roof")):
        for half in ((0, 1, 2, 3), (3, 4, 5, 0)):
            quad = [[c[k][0], y, c[k][2]] for k in half]
            shapes.append({"type": "quad", "vertices": oriented(quad, want), "material": mat})
    return shapes


def lights():
    shapes = []
    y = H - LIGHT_GAP
    s = LIGHT_SIZE / 2
    for cx, cz in ((0.0, -2.0), (-2.2, 1.0), (2.2, 1.0)):
        quad = [[cx - s, y, cz - s], [cx + s, y, cz - s], [cx + s, y, cz + s], [cx - s, y, cz + s]]
        shapes.append({"type": "quad", "vertices": oriented(quad, [0, -1, 0]), "material": "light",
                       "power": LIGHT_POWER})
    return shapes


def tetrahedron(cx, cz, edge, yaw_deg):
    """A regular tetrahedron standing on one face on the floor (y = 0), apex up."""
    rc = edge / math.sqrt(3)              # circumradius of the base triangle
    h = edge * math.sqrt(2.0 / 3.0)       # height
    pts = []
    for k in range(3):
        a = math.radians(yaw_deg + 120 * k)
        pts.append(rnd([cx + rc * math.cos(a), 0.0, cz + rc * math.sin(a)]))
    pts.append(rnd([cx, h, cz]))
    return pts


def objects():
    return [
        {"type": "sphere", "center": [-1.9, 0.75, -2.4], "radius": 0.75, "material": "mirror"},
        {"type": "sphere", "center": [0.6, 0.6, -0.4], "radius": 0.6, "material": "glass"},
        {"type": "sphere", "center": [1.9, 0.5, -1.5], "radius": 0.5, "material": "white"},
        {"type": "sphere", "center": [-2.2, 0.4, -0.5], "radius": 0.4, "material": "orange"},
        {"type": "tetrahedron", "vertices": tetrahedron(0.5, -3.0, 1.4, 20.0), "material": "mirror"},
        {"type": "tetrahedron", "vertices": tetrahedron(-0.7, -1.3, 1.0, -15.0), "material": "white"},
    ]


def inside_room(p, margin=0.0):
    """True when p is inside the hexagonal prism, at least `margin` from every wall/floor/roof."""
    apothem = R * math.sin(math.radians(60))
    if not (margin <= p[1] <= H - margin):
        return False
    for k in range(6):
        a = math.radians(60 * k + 30)   # outward direction of wall k (between corners k, k+1)
        d = p[0] * math.cos(a) - p[2] * math.sin(a)
        if d > apothem - margin:
            return False
    return True


def build():
    scene = {
        "tessera": 1,
        "camera": {
            "position": [1.2, 2.5, 4.1],
            "look_at": [-0.3, 0.7, -2.0],
            "up": [0, 1, 0],
            "fov": 55,
            "fov_axis": "x",
        },
        "film": {"width": 1920, "height": 1080},
        "render": {"spp": 64},
        "materials": MATERIALS,
        "shapes": room() + lights() + objects(),
    }
    # sanity: camera, lights and objects inside the room, objects on the floor, not overlapping
    assert inside_room(scene["camera"]["position"], 0.2)
    for s in scene["shapes"]:
        if s["type"] == "sphere":
            assert inside_room(s["center"], s["radius"]) and abs(s["center"][1] - s["radius"]) < 1e-9
        elif s["type"] == "tetrahedron":
            assert all(inside_room(p, 0.1) or p[1] == 0.0 for p in s["vertices"])
            assert min(p[1] for p in s["vertices"]) == 0.0
        elif "power" in s:
            assert all(inside_room(p, 0.0) and p[1] == H - LIGHT_GAP for p in s["vertices"])
    objs = [s for s in scene["shapes"] if s["type"] in ("sphere", "tetrahedron")]

    def bound(s):  # bounding circle on the floor
        if s["type"] == "sphere":
            return s["center"][0], s["center"][2], s["radius"]
        v = s["vertices"]
        return v[3][0], v[3][2], math.dist(v[0], [v[3][0], 0, v[3][2]])
    for i in range(len(objs)):
        for j in range(i + 1, len(objs)):
            (x1, z1, r1), (x2, z2, r2) = bound(objs[i]), bound(objs[j])
            assert math.hypot(x1 - x2, z1 - z2) > r1 + r2 + 0.1, (objs[i], objs[j])
    return scene


def dump(scene):
    text = json.dumps(scene, indent=2)
    num = r"(-?[\d.eE+-]+)"
    text = re.sub(r"\[\s*" + num + r",\s*" + num + r",\s*" + num + r"\s*\]", r"[\1, \2, \3]", text)
    return text + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, default=ROOT / "scenes/hexroom.json")
    ap.add_argument("--check", action="store_true")
    args = ap.parse_args()
    scene = build()
    text = dump(scene)
    assert json.loads(text) == scene
    if args.check:
        same = args.out.exists() and args.out.read_text() == text
        print(f"{args.out}: {'up to date' if same else 'DIFFERS from generated'}")
        return 0 if same else 1
    args.out.write_text(text)
    n = {}
    for s in scene["shapes"]:
        n[s["type"]] = n.get(s["type"], 0) + 1
    print(f"wrote {args.out}: {n}; windings checked")
    return 0


if __name__ == "__main__":
    sys.exit(main())
