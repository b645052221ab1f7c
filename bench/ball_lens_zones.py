#!/usr/bin/env python3
"""Where a ball lens's caustic comes from, and what models of the lamps' images gain there.

An exact trace (vector refraction at the sphere, the Fresnel choices as the path tracer makes
them, up to two internal reflections) of the light that diffuse points on the floor around each
glass sphere receive from the scene's area lamps through it, and the variance of the one-sample
bounce estimate of that light under the bounce mixture of
worker/render/guiding/target_mixture.h, with the scene's targets and lamp images built as
worker/render/guiding/specular_targets.cpp builds them (the same formulas and rules, in numpy
double), and with candidate models of the lens in their place (MODELS). docs/renderer.md and
BENCHMARKS.md, "Tried, and why not" (images of the ball lens's zones: measured, not built).

Prints, per (lamp, glass sphere): the paraxial image's distance and, for rays from the lamp's
centre at impact parameters b (the line's distance from the centre, the same on both sides of
the lens), where the exit ray crosses the axis (s / R) and its angle to the axis. With --where,
for each floor point: the caustic's irradiance E and, per lamp and number of internal
reflections, its share, the weighted 10/50/90th percentiles of b / R and of the angle between
the light's direction and the paraxial image cone's axis (in units of the cone's half-angle),
and the share inside that cone. Then, per model: the caustic variance summed over the floor
points (absolute, as pixels add it), against the first model named, and the "sky excess": the
second moment minus 1 of the estimate of a uniform sky of radiance 1, mean over the points (0
for the cosine alone: what the cones cost where they hold no light). --bounds adds the ideal
(half of the bounces exactly in proportion to the light) and an oracle cone per point.

Only the hexroom-style JSON scene (quads with 'power' as lamps, spheres, tetrahedra) is read.

Usage (repository root; PY is a Python with numpy 2, e.g. the .venv-bench of bench/README.md):
  $PY bench/ball_lens_zones.py scenes/hexroom.json [--where] [--at X,Y,Z] [--bounds] \
      [--models paraxial,targets,z4,...] [--grid 0.1 --extent 1.0 --dirs 30000]
"""
import argparse

import numpy as np

from ball_lens_optics import (CAP, MASS_IMAGE, Scene, ball_lens_image, build_sources, hit_lamps, source,
                              trace_through_sphere, unit)


class Mixture:
    """TargetMixture::init and pdf (target_mixture.h), in double."""

    def __init__(self, sources, x, n):
        self.axes, self.cosmax, self.cosmin, self.dens, self.p = [], [], [], [], []
        q, mc = [], []
        for s in sources:
            gate = s["always"] or np.dot(s["g"], x) > s["go"]
            d = s["c"] - x
            e = s["w"] - x
            if not s["always"] and np.dot(d, e) < 0:
                d = -d
            dn = np.dot(d, n)
            dist2 = np.dot(d, d)
            if not gate or dn <= 0 or dist2 <= s["r"] ** 2:
                continue
            inv = 1 / np.sqrt(dist2)
            if not s["always"]:
                tw = np.dot(e, d) * inv
                reach = s["wr"] + s["r"] * tw * inv
                if np.dot(e, e) - tw * tw > reach * reach:
                    continue
            if s["band"] is not None:
                ax, lo2, hi2 = s["band"]
                u = x - s["c"]
                proj = np.dot(u, ax)
                if not (lo2 * np.dot(u, u) <= proj * proj <= hi2 * np.dot(u, u)):
                    continue
            sin2 = min(1.0, s["r"] ** 2 * inv * inv)
            omc = sin2 / (1 + np.sqrt(1 - sin2))
            cos_axis = dn * inv
            # An annulus: the cap between the inner sine fraction's cone and the outer one.
            a = s.get("inner", 0.0)
            sin2_in = a * a * sin2
            omc_in = sin2_in / (1 + np.sqrt(1 - sin2_in))
            qk = s["mass"] * 2 * (omc - omc_in) * cos_axis
            if qk <= 0:
                continue
            self.axes.append(d * inv)
            self.cosmax.append(1 - omc)
            self.cosmin.append(1 - omc_in if a > 0 else 2.0)
            q.append(qk)
            mc.append(s["mass"] * cos_axis * omc / (omc - omc_in))
        q = np.array(q)
        scale = CAP / q.sum() if q.sum() > CAP else 1.0
        self.p = q * scale
        self.dens = np.array(mc) * scale / np.pi
        self.p_cos = 1 - self.p.sum()
        self.n = n
        self.axes = np.array(self.axes).reshape(-1, 3)
        self.cosmax = np.array(self.cosmax)

    def pdf(self, w):
        cos_n = w @ self.n
        pdf = np.where(cos_n > 0, self.p_cos * cos_n / np.pi, 0.0)
        if len(self.p):
            cw = w @ self.axes.T
            inside = (cw >= self.cosmax[None, :]) & (cw < np.array(self.cosmin)[None, :])
            pdf = pdf + (inside * self.dens[None, :]).sum(1)
        return pdf


def cone_directions(x, c, R, N, rng):
    """N directions uniform in the cone of the sphere (c, R) seen from x, and its solid angle."""
    d = c - x
    dist = np.linalg.norm(d)
    axis = d / dist
    cos_max = np.sqrt(max(0.0, 1 - (R / dist) ** 2))
    u1, u2 = rng.random(N), rng.random(N)
    cos_t = 1 - u1 * (1 - cos_max)
    sin_t = np.sqrt(1 - cos_t ** 2)
    phi = 2 * np.pi * u2
    t1 = unit(np.cross(axis, [1.0, 0, 0] if abs(axis[0]) < 0.9 else [0, 1.0, 0]))
    t2 = np.cross(axis, t1)
    w = (sin_t * np.cos(phi))[:, None] * t1 + (sin_t * np.sin(phi))[:, None] * t2 + cos_t[:, None] * axis
    return w, 2 * np.pi * (1 - cos_max)


def caustic_samples(scene, g, x, n, N, rng):
    """Directions in the glass sphere's cone from x, each with the radiance it brings from a lamp
    through the sphere (the sum over reflect/refract sequences, each weighted by its probability:
    the one-sample estimate's second moment needs the probabilities, kept per sequence)."""
    w, omega = cone_directions(x, g["c"], g["R"], N, rng)
    cos_n = w @ n
    seqs = []
    for k, (o, wo, prob, p1) in enumerate(trace_through_sphere(x, w, g["c"], g["R"], g["n"])):
        L, which = hit_lamps(o + 1e-9 * wo, wo, scene.lamps)
        seqs.append((k, prob, L, which, o, wo, p1))
    return w, omega, np.maximum(cos_n, 0), seqs


def lens_rays(c, R, ior, L, b):
    """Rays from the point L through the ball lens (c, R, ior) at impact parameters b (in the
    meridional plane, distances from the axis line of L and c). Returns per ray the axis
    crossing s (the distance from c along the axis, away from L; negative: on L's side) and the
    cosine of the exit ray's angle to the axis."""
    d = np.linalg.norm(L - c)
    z = (c - L) / d
    y = unit(np.cross(z, [1.0, 0, 0] if abs(z[0]) < 0.9 else [0, 1.0, 0]))
    y = unit(np.cross(np.cross(z, y), z))
    sa = b / d
    w = np.sqrt(1 - sa * sa)[:, None] * z + sa[:, None] * y
    o, wo, prob, _ = next(trace_through_sphere(np.repeat(L[None], len(b), 0), w, c, R, ior, 0))
    oy = (o - c) @ y
    oz = (o - c) @ z
    wy = wo @ y
    wz = wo @ z
    s = oz - oy * wz / np.where(wy != 0, wy, -1e-30)
    return s, wz


class Zones:
    """Zone images: the entry annuli [edges[k], edges[k + 1]] (as b / R) of each (lamp, glass)
    pair, each an image at its rays' mean axis crossing, radius from the crossings' spread and
    the lamp's size, gated by the band of angles its rays make with the axis."""

    def __init__(self, edges, margin=0.0, band_margin=0.0, use_band=True, max_images=16, keep_paraxial=True,
                 spread=0.5):
        self.edges, self.margin, self.band_margin = edges, margin, band_margin
        self.use_band, self.max_images, self.spread = use_band, max_images, spread
        self.keep_paraxial = keep_paraxial

    def __call__(self, c, R, ior, lamp):
        L, rL = lamp["c"], lamp["r"]
        d = np.linalg.norm(L - c)
        z = (c - L) / d
        out = []
        sin_l = rL / d
        for b0, b1 in zip(self.edges[:-1], self.edges[1:]):
            b = R * np.linspace(b0, b1, 17)
            s, cz = lens_rays(c, R, ior, L, b)
            ok = np.isfinite(s) & (cz > 0)
            if ok.sum() < 2:
                continue
            s, cz = s[ok], cz[ok]
            s_mid = 0.5 * (s.min() + s.max())
            sin_t = np.sqrt(1 - cz * cz)
            r = self.spread * (s.max() - s.min()) * sin_t.max() + abs(s_mid) * sin_l + self.margin * R
            band = None
            if self.use_band:
                # The band widened by the lamp's angular radius and band_margin (radians).
                th = np.arccos(np.clip(cz, -1, 1))
                lo = max(0.0, th.min() - np.arcsin(sin_l) - self.band_margin)
                hi = min(np.pi / 2, th.max() + np.arcsin(sin_l) + self.band_margin)
                band = (z, np.cos(hi) ** 2, np.cos(lo) ** 2)
            im = source(c + z * s_mid, r, z, np.dot(z, c), c, R, MASS_IMAGE, False, band)
            # Scored by the zone's share of the lens's intercepted light (its annulus's area).
            im["score_scale"] = b1 * b1 - b0 * b0
            out.append(im)
        return out


def oracle_source(x, w, wt, share, mass):
    """The cone an oracle would aim at x: around the light's mean direction, just wide enough to
    hold `share` of it (weights wt over directions w), as a target-like source (no gate)."""
    axis = unit((w * wt[:, None]).sum(0))
    ang = np.arccos(np.clip(w @ axis, -1, 1))
    half = np.percentile(ang[wt > 0], 100 * share, method="inverted_cdf", weights=wt[wt > 0])
    centre = x + 10.0 * axis
    return source(centre, 10.0 * np.sin(half), [0, 0, 0], -np.inf, centre, 10.0 * np.sin(half), mass, True)


def evaluate(scene, models, points, n, N, rng, verbose=False, bounds=()):
    """For each model (name -> sources), the caustic's variance summed over `points` (the one-
    sample bounce estimate of the light through the glass: second moment minus mean squared,
    the Fresnel choices included) and the mean excess second moment of a uniform sky of radiance
    1 (0 for the cosine alone: what the cones cost where they hold no light).

    `bounds` adds, by name: "ideal" (half the bounces exactly in proportion to the caustic's
    light, the cap's most) and "oracle" (in place of the glass's lamp images of `models`'s
    first entry, one cone per point fitted to its light: holding 80 %, mass 16)."""
    names = list(models) + list(bounds)
    var = {k: 0.0 for k in names}
    sky = {k: 0.0 for k in models}
    first = list(models.values())[0]
    n_targets = len(scene.glass) + len(scene.mirror_spheres) + len(scene.mirror_meshes)
    not_glass = [s for s in first[n_targets:]
                 if not any(np.allclose(s["w"], g["c"]) and s["wr"] == g["R"] for g in scene.glass)]
    for x in points:
        mixes = {k: Mixture(src, x, n) for k, src in models.items()}
        # The sky: cosine-distributed directions, E[(cos / pi) / pdf] - 1.
        u1, u2 = rng.random(20000), rng.random(20000)
        r, phi = np.sqrt(u1), 2 * np.pi * u2
        t1 = np.array([1.0, 0, 0]) if abs(n[0]) < 0.9 else np.array([0, 0, 1.0])
        t1 = unit(np.cross(n, t1))
        t2 = np.cross(n, t1)
        cz = np.sqrt(1 - u1)
        w = (r * np.cos(phi))[:, None] * t1 + (r * np.sin(phi))[:, None] * t2 + cz[:, None] * n
        for k, m in mixes.items():
            sky[k] += (cz / np.pi / m.pdf(w)).mean() - 1
        for g in scene.glass:
            if np.linalg.norm(x - g["c"]) <= g["R"] * 1.0001:
                continue
            w, omega, cos_n, seqs = caustic_samples(scene, g, x, n, N, rng)
            v = np.zeros(N)  # sum over sequences of prob * L^2 (second moment's integrand part)
            m1 = np.zeros(N)
            for _, prob, L, _, _, _, _ in seqs:
                v += prob * L * L
                m1 += prob * L
            f = cos_n / np.pi
            mean = omega * (f * m1).mean()
            line = []
            pdfs = {k: m.pdf(w) for k, m in mixes.items()}
            if mean > 0 and "ideal" in bounds:
                pdfs["ideal"] = 0.5 * f + 0.5 * f * m1 / mean
            if mean > 0 and "oracle" in bounds:
                cone = oracle_source(x, w, f * m1, 0.8, 16.0)
                pdfs["oracle"] = Mixture(first[:n_targets] + [cone] + not_glass, x, n).pdf(w)
            for k, p in pdfs.items():
                second = omega * np.where(v > 0, f * f * v / np.where(p > 0, p, 1), 0).mean()
                var[k] += second - mean * mean
                line.append(f"{k} {second - mean * mean:.4g}")
            if verbose and mean > 0:
                print(f"  x {x.round(2)} E {mean:.4g}: " + ", ".join(line))
    return var, {k: v / len(points) for k, v in sky.items()}


def where_from(scene, g, x, n, N, rng):
    """The caustic at x through glass sphere g: its irradiance, and per lamp the energy-weighted
    impact parameter (b / R) and angle between the light's direction and the paraxial image
    cone's axis (in units of the cone's angular radius), and the share inside that cone."""
    w, omega, cos_n, seqs = caustic_samples(scene, g, x, n, N, rng)
    e_total = sum((prob * L * cos_n).sum() for _, prob, L, _, _, _, _ in seqs) * omega / N / np.pi
    rows = []
    for i, lamp in enumerate(scene.lamps):
        a = unit(lamp["c"] - g["c"])
        im = ball_lens_image(g["c"], g["R"], g["n"], lamp["c"], lamp["r"])
        for k, prob, L, which, o, wo, p1 in seqs:
            m = (which == i) & (prob * L * cos_n > 0)
            if not m.any():
                continue
            wt = (prob * L * cos_n)[m]
            e = wt.sum() * omega / N / np.pi
            # The impact parameter (the line's distance from the centre, the same on both sides of
            # the lens): the zone, whichever lamp point the ray ends on.
            b = np.linalg.norm(np.cross(x - g["c"], w[m]), axis=1) / g["R"]
            # The paraxial cone at x (toward I or 2x - I, as the mixture aims it).
            d = im["c"] - x
            if np.dot(d, g["c"] - x) < 0:
                d = -d
            dist = np.linalg.norm(d)
            half = np.arcsin(min(1, im["r"] / dist))
            ang = np.arccos(np.clip(w[m] @ (d / dist), -1, 1)) / half
            q = lambda v: np.percentile(v, [10, 50, 90], method="inverted_cdf", weights=wt)
            rows.append((i, k, e / e_total, q(b), q(ang), (wt * (ang <= 1)).sum() / wt.sum()))
    return e_total, rows


def light_map(scene, g, x, n, N, rng, mixture):
    """At x: the caustic's irradiance, the lens's solid angle, the share of it lit and the share
    holding 90 % of the light; and per cone of `mixture` (index, probability, half-angle in
    degrees, share of the light inside, weighted 50/90/99th percentiles of the light's angle
    from its axis in units of its half-angle)."""
    w, omega, cos_n, seqs = caustic_samples(scene, g, x, n, N, rng)
    wt = np.zeros(N)
    for _, prob, L, _, _, _, _ in seqs:
        wt += prob * L
    wt *= cos_n
    if wt.sum() <= 0:
        return None
    # How much of the lens's cone is lit, and how much of it holds 90 % of the light.
    lit = (wt > 0).mean()
    ranked = np.sort(wt)[::-1]
    fill90 = (np.searchsorted(np.cumsum(ranked) / ranked.sum(), 0.9) + 1) / len(wt)
    out = []
    for k in range(len(mixture.p)):
        cosw = w @ mixture.axes[k]
        half = np.arccos(mixture.cosmax[k])
        ang = np.arccos(np.clip(cosw, -1, 1)) / half
        inside = wt[ang <= 1].sum() / wt.sum()
        q = np.percentile(ang[wt > 0], [50, 90, 99], method="inverted_cdf", weights=wt[wt > 0])
        out.append((k, mixture.p[k], np.degrees(half), inside, q))
    return wt.sum() * omega / N / np.pi, omega, lit, fill90, out


class LensAnnulus:
    """Per (lamp, glass): in place of (or beside) the paraxial image, the lens's own cone from x
    without its inner part (sine fraction `inner`), gated to the lens's far side from the lamp."""

    def __init__(self, inner, keep_paraxial, mass=MASS_IMAGE, max_images=8):
        self.inner, self.keep_paraxial, self.mass, self.max_images = inner, keep_paraxial, mass, max_images

    def __call__(self, c, R, ior, lamp):
        a = unit(lamp["c"] - c)
        im = source(c, R, -a, np.dot(-a, c), c, R, self.mass, False)
        im["inner"] = self.inner
        return [im]


MODELS = {
    # The renderer's images (the paraxial image of each lamp through each glass sphere), 8 kept.
    "paraxial": "paraxial",
    # No lamp images at all: the targets' bounding cones.
    "targets": None,
    # The renderer's rule with every image kept (11 in hexroom: all three glass images).
    "paraxial16": "paraxial16",
    # The zone model: entry annuli [edges] of b / R per (lamp, glass) pair, beside the paraxial
    # image or in its place ("-only"), at most 16 images.
    "z4": Zones([0, 0.5, 0.7, 0.85, 1.0]),
    "z4-noband": Zones([0, 0.5, 0.7, 0.85, 1.0], use_band=False),
    "z4-only": Zones([0, 0.5, 0.7, 0.85, 1.0], keep_paraxial=False),
    "z3": Zones([0, 0.6, 0.85, 1.0]),
    "z3-margins": Zones([0, 0.6, 0.85, 1.0], margin=0.05, band_margin=0.05),
    "z2": Zones([0, 0.8, 1.0]),
    "z2-only": Zones([0, 0.8, 1.0], keep_paraxial=False),
    # The lens's own cone less its inner part (sine fraction), per lamp, gated to the far side.
    "annulus0": LensAnnulus(0.0, False),
    "annulus0.3": LensAnnulus(0.3, False),
    "annulus0.45": LensAnnulus(0.45, False),
    "annulus0.3+p": LensAnnulus(0.3, True, max_images=11),
    "annulus0.45+p": LensAnnulus(0.45, True, max_images=11),
    # The renderer's images with the glass's mass factor changed (4 in the renderer).
    "glass-mass2": ("mass", 2.0),
    "glass-mass8": ("mass", 8.0),
    "glass-mass16": ("mass", 16.0),
}


def model_sources(scene, name, zones):
    """The sources of model `name` (MODELS[name] = zones)."""
    if zones is None:
        return build_sources(scene)[:len(scene.glass) + len(scene.mirror_spheres) + len(scene.mirror_meshes)]
    if zones == "paraxial":
        return build_sources(scene)
    if isinstance(zones, tuple) and zones[0] == "mass":
        srcs = build_sources(scene)
        glass_images = [s for s in srcs[len(scene.glass) + len(scene.mirror_spheres) + len(scene.mirror_meshes):]
                        if any(np.allclose(s["w"], g["c"]) and s["wr"] == g["R"] for g in scene.glass)]
        for s in glass_images:
            s["mass"] = zones[1]
        return srcs
    if zones == "paraxial16":
        return build_sources(scene, max_images=16)
    return build_sources(scene, zones, paraxial=zones.keep_paraxial)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene")
    ap.add_argument("--dirs", type=int, default=200000)
    ap.add_argument("--grid", type=float, default=0.15, help="floor grid step, m")
    ap.add_argument("--extent", type=float, default=1.2, help="floor grid half-size around the contact point, m")
    ap.add_argument("--where", action="store_true", help="print where the light comes from")
    ap.add_argument("--models", default=",".join(MODELS), help="comma-separated names of MODELS; the first is the"
                    " reference")
    ap.add_argument("--bounds", action="store_true", help="also the ideal and the oracle cone (evaluate())")
    ap.add_argument("--at", action="append", default=[], help="X,Y,Z: print the light map at this floor point"
                    " (light_map) under the renderer's mixture")
    ap.add_argument("--verbose", action="store_true")
    args = ap.parse_args()
    scene = Scene(args.scene)
    rng = np.random.default_rng(1)
    print(f"{len(scene.lamps)} lamps, {len(scene.glass)} glass spheres, scene radius {scene.radius:.3f}")
    n = np.array([0.0, 1.0, 0.0])
    offsets = np.arange(-args.extent, args.extent + 1e-9, args.grid)
    for g in scene.glass:
        base = g["c"] - np.array([0, g["R"], 0])
        for lamp in scene.lamps:
            d = np.linalg.norm(lamp["c"] - g["c"])
            f = g["n"] * g["R"] / (2 * (g["n"] - 1))
            print(f"glass c={g['c']} R={g['R']} n={g['n']}; lamp {lamp['c']} r={lamp['r']:.3f}: d={d:.3f}, "
                  f"paraxial image at {f * d / (d - f) / g['R']:.2f} R, axis {unit(g['c'] - lamp['c']).round(3)}")
            b = g["R"] * np.array([0.05, 0.3, 0.5, 0.6, 0.7, 0.8, 0.85, 0.9, 0.95, 0.99])
            s, cz = lens_rays(g["c"], g["R"], g["n"], lamp["c"], b)
            print("   b/R -> axis crossing s/R, exit angle (deg): " + ", ".join(
                f"{bb / g['R']:.2f}: {ss / g['R']:.2f} {np.degrees(np.arccos(c)):.0f}" for bb, ss, c in zip(b, s, cz)))
        if args.where:
            for ix in offsets:
                for iz in offsets:
                    x = base + np.array([ix, 0, iz])
                    if np.hypot(ix, iz) < 0.05:
                        continue
                    e, rows = where_from(scene, g, x, n, args.dirs, rng)
                    if e <= 0:
                        continue
                    print(f"x = floor {ix:+.2f} {iz:+.2f} (rho {np.hypot(ix, iz) / g['R']:.2f} R): E = {e:.4g}")
                    for i, k, share, bq, ang, inside in rows:
                        if share < 0.02:
                            continue
                        print(f"   lamp {i} internal {k}: {100 * share:5.1f} %  b/R {bq[0]:.2f} {bq[1]:.2f} {bq[2]:.2f}"
                              f"  angle/paraxial half {ang[0]:.2f}"
                              f" {ang[1]:.2f} {ang[2]:.2f}  in paraxial cone {100 * inside:.0f} %")
    for at in args.at:
        x = np.array([float(v) for v in at.split(",")])
        m = Mixture(build_sources(scene), x, n)
        for g in scene.glass:
            res = light_map(scene, g, x, n, args.dirs, rng, m)
            if res is None:
                continue
            e, omega, lit, fill90, cones = res
            print(f"at {x}: E {e:.4g}; the lens's cone {omega:.2f} sr, {100 * lit:.0f} % of it lit, 90 % of the light"
                  f" in {100 * fill90:.0f} % of it; the renderer's cones (cosine {m.p_cos:.3f}):")
            for k, p, half, inside, q in cones:
                print(f"   cone {k}: p {p:.3f}, half-angle {half:.1f} deg, {100 * inside:.0f} % of the light inside,"
                      f" the light at {q[0]:.2f} / {q[1]:.2f} / {q[2]:.2f} of the half-angle")
    if args.at:
        return
    names = args.models.split(",")
    models = {k: model_sources(scene, k, MODELS[k]) for k in names}
    for k, srcs in models.items():
        print(f"{k}: {len(srcs)} sources")
    points = [g["c"] - np.array([0, g["R"], 0]) + np.array([ix, 0, iz])
              for g in scene.glass for ix in offsets for iz in offsets if np.hypot(ix, iz) >= 0.05]
    bounds = ("ideal", "oracle") if args.bounds else ()
    var, sky = evaluate(scene, models, points, n, args.dirs, rng, args.verbose, bounds)
    ref = var[names[0]]
    for k in names + list(bounds):
        sky_text = f", sky excess {sky[k]:.4f}" if k in sky else ""
        print(f"{k:12s} caustic variance summed over {len(points)} floor points {var[k]:.5g} (x{var[k] / ref:.3f})"
              + sky_text)


if __name__ == "__main__":
    main()
