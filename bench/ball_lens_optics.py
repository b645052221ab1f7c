"""The scene and the specular targets' optics of bench/ball_lens_zones.py: the hexroom-style JSON
scene (quads with 'power' as lamps, spheres, tetrahedra), refraction through a glass sphere, and
the targets and lamp images built as worker/render/guiding/specular_targets.cpp builds them (the
same formulas and rules, in numpy double).
"""
import json

import numpy as np

MASS_TARGET, MASS_IMAGE, CAP = 1.0, 4.0, 0.5
LENS_ABERRATION, MIRROR_ABERRATION = 0.1, 0.21
MAX_IMAGES, MAX_FLAT = 8, 16


def unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def bounding_sphere(pts):
    pts = np.asarray(pts, float)
    lo, hi = pts.min(0), pts.max(0)
    bc = 0.5 * (lo + hi)
    br2 = ((pts - bc) ** 2).sum(1).max()
    mn, mx = pts.argmin(0), pts.argmax(0)
    axis = int(np.argmax([((pts[mx[a]] - pts[mn[a]]) ** 2).sum() for a in range(3)]))
    c = 0.5 * (pts[mn[axis]] + pts[mx[axis]])
    r = 0.5 * np.linalg.norm(pts[mx[axis]] - pts[mn[axis]])
    for p in pts:
        dist = np.linalg.norm(p - c)
        if dist > r:
            nr = 0.5 * (r + dist)
            c = c + (p - c) * ((nr - r) / dist)
            r = nr
    rr2 = ((pts - c) ** 2).sum(1).max()
    return (c, np.sqrt(rr2)) if rr2 < br2 else (bc, np.sqrt(br2))


class Scene:
    """The hexroom-style JSON scene: quads (lamps where 'power' is given), spheres, tetrahedra."""

    def __init__(self, path):
        d = json.load(open(path))
        mats = d["materials"]
        self.lamps, self.glass, self.mirror_spheres, self.mirror_meshes = [], [], [], []
        allpts = []
        for s in d["shapes"]:
            m = mats.get(s.get("material"), {})
            if s["type"] == "quad":
                v = np.array(s["vertices"], float)
                allpts += list(v)
                if "power" in s:
                    e1, e2 = v[1] - v[0], v[3] - v[0]
                    n = unit(np.cross(e1, e2))
                    area = np.linalg.norm(np.cross(e1, e2))
                    # Emits toward the room (the side facing the floor, y down here).
                    if n[1] > 0:
                        n = -n
                    radiance = s["power"] / (np.pi * area)
                    c, r = bounding_sphere(v)
                    self.lamps.append(dict(v=v, n=n, radiance=radiance, c=c, r=r, power=radiance * area))
            elif s["type"] == "sphere":
                c, r = np.array(s["center"], float), float(s["radius"])
                allpts += [c - r, c + r]
                if m.get("type") == "glass":
                    self.glass.append(dict(c=c, R=r, n=float(m.get("ior", 1.5))))
                elif m.get("type") == "mirror":
                    self.mirror_spheres.append(dict(c=c, R=r))
            elif s["type"] == "tetrahedron":
                v = np.array(s["vertices"], float)
                allpts += list(v)
                if m.get("type") == "mirror":
                    tris = [(0, 1, 2), (0, 1, 3), (1, 2, 3), (0, 2, 3)]
                    self.mirror_meshes.append([v[list(t)] for t in tris])
        _, self.radius = bounding_sphere(allpts)


def refract(w, n, eta):
    """w toward the surface, n facing w's side (dot(w, n) < 0), eta = n_i / n_t. Returns the
    refracted direction and the Fresnel reflectance (dielectric, unpolarised)."""
    cos_i = -np.sum(w * n, -1)
    sin2_t = eta * eta * (1 - cos_i * cos_i)
    tir = sin2_t >= 1
    cos_t = np.sqrt(np.maximum(0, 1 - sin2_t))
    t = eta * w + (eta * cos_i - cos_t)[..., None] * n
    rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t)
    rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t)
    fr = np.where(tir, 1.0, 0.5 * (rs * rs + rp * rp))
    return t, fr


def trace_through_sphere(x, w, c, R, ior, max_internal=2):
    """Rays from x along w (unit, N x 3) into the sphere. Yields (exit origin, exit direction,
    probability of this reflect/refract sequence, entry point) for 0..max_internal internal
    reflections; rays missing the sphere have probability 0."""
    oc = x - c
    b = np.sum(oc * w, -1)
    cc = np.sum(oc * oc, -1) - R * R
    disc = b * b - cc
    hit = disc > 0
    t = -b - np.sqrt(np.maximum(disc, 0))
    hit &= t > 0
    p1 = x + t[:, None] * w
    n1 = (p1 - c) / R
    d, fr = refract(w, n1, 1.0 / ior)
    prob = np.where(hit, 1 - fr, 0.0)
    p = p1
    for k in range(max_internal + 1):
        # Inside: the chord from p along d.
        n_in = (p - c) / R
        chord = -2 * R * np.sum(d * n_in, -1)
        q = p + chord[:, None] * d
        n2 = (q - c) / R
        out, fr2 = refract(d, -n2, ior)
        yield q, unit(out), prob * (1 - fr2), p1
        # One more internal reflection.
        prob = prob * fr2
        d = d - 2 * np.sum(d * n2, -1)[:, None] * n2
        p = q


def hit_lamps(o, w, lamps):
    """Radiance arriving at o from direction w from the lamps (their emitting side), 0 if none."""
    L = np.zeros(len(o))
    which = np.full(len(o), -1)
    for i, lamp in enumerate(lamps):
        v, n = lamp["v"], lamp["n"]
        denom = np.sum(w * n, -1)
        ok = denom < 0  # the ray meets the emitting side
        t = np.sum((v[0] - o) * n, -1) / np.where(ok, denom, 1)
        ok &= t > 0
        p = o + t[:, None] * w
        e1, e2 = v[1] - v[0], v[3] - v[0]
        u = np.sum((p - v[0]) * e1, -1) / np.dot(e1, e1)
        s = np.sum((p - v[0]) * e2, -1) / np.dot(e2, e2)
        ok &= (u >= 0) & (u <= 1) & (s >= 0) & (s <= 1)
        L = np.where(ok, lamp["radiance"], L)
        which = np.where(ok, i, which)
    return L, which


# --- the sources of worker/render/guiding/specular_targets.cpp ------------------------------------

def source(center, r, gate_n, gate_off, win_c, win_r, mass, always, band=None):
    return dict(c=np.asarray(center, float), r=float(r), g=np.asarray(gate_n, float), go=float(gate_off),
                w=np.asarray(win_c, float), wr=float(win_r), mass=mass, always=always, band=band)


def ball_lens_image(c, R, ior, L, rL):
    d = np.linalg.norm(L - c)
    a = (L - c) / d
    f = ior * R / (2 * (ior - 1))
    if abs(d - f) <= 1e-3 * d:
        return None
    di = f * d / (d - f)
    return source(c - a * di, abs(di) / d * rL + LENS_ABERRATION * R, -a, np.dot(-a, c), c, R, MASS_IMAGE, False)


def convex_mirror_image(c, R, L, rL):
    d = np.linalg.norm(L - c)
    a = (L - c) / d
    obj, f = d - R, -0.5 * R
    di = f * obj / (obj - f)
    return source(c + a * (R + di), abs(di) / obj * rL + MIRROR_ABERRATION * R, a, np.dot(a, c), c, R,
                  MASS_IMAGE, False)


def flat_mirror_image(face, inside, L, rL):
    n = unit(np.cross(face[1] - face[0], face[2] - face[0]))
    off = np.dot(n, face[0])
    s = np.dot(n, L) - off
    if s < 0:
        n, off, s = -n, -off, -s
    if not s > 0 or np.dot(n, inside) - off > 1e-4 * abs(s):
        return None
    wc, wr = bounding_sphere(face)
    return source(L - 2 * s * n, rL, n, off, wc, wr, MASS_IMAGE, False), wc, wr, n


def build_sources(scene, zone_model=None, paraxial=True, max_images=None):
    """Targets then images, as SpecularTargets builds them; zone_model(c, R, ior, lamp) returns
    extra glass images (scored like the paraxial one)."""
    targets = []  # (centre, radius, kind, data)
    for g in scene.glass:
        targets.append((g["c"], g["R"], "glass", g))
    for m in scene.mirror_spheres:
        targets.append((m["c"], m["R"], "msphere", m))
    for tris in scene.mirror_meshes:
        c, r = bounding_sphere(np.concatenate(tris))
        targets.append((c, r, "mesh", tris))
    sources = [source(c, r, [0, 0, 0], -np.inf, c, r, MASS_TARGET, True) for c, r, _, _ in targets]
    scored = []
    for lamp in scene.lamps:
        for c, r, kind, data in targets:
            d = np.linalg.norm(lamp["c"] - c)
            frac = min(0.5, r * r / (4 * d * d))
            if kind == "glass":
                ims = []
                if paraxial:
                    im = ball_lens_image(c, r, data["n"], lamp["c"], lamp["r"])
                    if im:
                        ims.append(im)
                if zone_model:
                    ims += zone_model(c, r, data["n"], lamp)
                for im in ims:
                    scored.append((lamp["power"] * frac * im.get("score_scale", 1.0), im))
            elif kind == "msphere":
                scored.append((lamp["power"] * frac, convex_mirror_image(c, r, lamp["c"], lamp["r"])))
            else:
                pts = np.concatenate(data)
                inside = pts.mean(0)
                for face in data:
                    res = flat_mirror_image(face, inside, lamp["c"], lamp["r"])
                    if res:
                        im, wc, wr, n = res
                        to = lamp["c"] - wc
                        dist = np.linalg.norm(to)
                        cos_tilt = np.dot(n, to) / dist
                        scored.append((lamp["power"] * min(0.5, wr * wr * cos_tilt / (4 * dist * dist)), im))
    order = sorted(range(len(scored)), key=lambda i: -scored[i][0])  # stable: ties keep order
    if max_images is None:
        max_images = MAX_IMAGES if zone_model is None else zone_model.max_images
    return sources + [scored[i][1] for i in order[:max_images]]
