#!/usr/bin/env python3
"""Mitsuba 3.9.1's hits of a few rays on the SDF grid torus (tests/data/mitsuba/sdfgrid/
torus_sdfgrid.vol, to_world identity: the grid spans [0, 1]^3), with both normal modes: the
reference of SdfGrid.TorusHitsMatchMitsuba (sdf_grid_test.cpp). Prints one C++ initializer per
ray: origin, direction, t, geometric normal, smooth normal, analytic shading normal.

Usage, from the repository root (PY: a Python with Mitsuba 3.9.1):
  $PY worker/render/geometry/mitsuba_sdfgrid_rays.py
"""
import os

import mitsuba as mi

mi.set_variant("scalar_rgb")
HERE = os.path.dirname(os.path.abspath(__file__))
VOL = os.path.normpath(os.path.join(HERE, "../../../tests/data/mitsuba/sdfgrid/torus_sdfgrid.vol"))
RAYS = [((0.5, 0.5, -1.0), (0.0, 0.0, 1.0)),
        ((0.31, 0.52, -1.0), (0.0, 0.0, 1.0)),
        ((-1.0, 0.45, 0.52), (1.0, 0.0, 0.0)),
        ((0.5, -1.0, 0.5), (0.0, 1.0, 0.0)),
        ((-0.5, -0.4, -0.3), (1.0, 0.9, 0.85)),
        ((1.6, 1.3, 1.5), (-1.0, -0.75, -1.1))]


def hits(normals):
    scene = mi.load_dict({"type": "scene", "grid": {"type": "sdfgrid", "filename": VOL,
                                                      "normals": normals}})
    out = []
    for o, d in RAYS:
        si = scene.ray_intersect(mi.Ray3f(o, d))
        out.append((float(si.t), list(si.n), list(si.sh_frame.n)))
    return out


def fmt(v):
    return "{" + ", ".join(f"{x:.9g}" for x in v) + "}"


for (o, d), smooth, analytic in zip(RAYS, hits("smooth"), hits("analytic")):
    print(f"    {{{fmt(o)}, {fmt(d)}, {smooth[0]:.9g}, {fmt(smooth[1])}, {fmt(smooth[2])}, {fmt(analytic[2])}}},")
