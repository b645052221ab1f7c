"""What the mitsuba_*.py reference scripts share: the directions they evaluate Mitsuba 3's BSDFs
at, the loop that writes eval() and pdf() at them, and the sample() mean that estimates an
albedo.

Directions are in the local frame: wo towards the camera, wi the other one (Mitsuba calls them
si.wi and wo). eval() is f |cos wi| per channel, in radiance transport. Point values need the
scalar_rgb variant, albedos the llvm_ad_rgb one: each script selects its variant before it
calls these.
"""
import math

import drjit as dr
import mitsuba as mi


def rgb(v):
    return {"type": "rgb", "value": v}


def direction(theta, phi):
    return [math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta)]


# (theta_o, phi_o, theta_i, phi_i) in radians: reflections near and far from the mirror
# direction, grazing ones, and pairs across the surface, from both sides.
PAIRS = [
    (0.3, 0.2, 0.35, 0.2 + math.pi),
    (0.7, 0.5, 0.6, 0.5 + math.pi + 0.3),
    (1.2, 1.0, 0.2, 2.0),
    (1.45, 0.1, 1.4, math.pi + 0.2),
    (0.0, 0.0, 0.9, 0.7),
    (0.5, 0.3, math.pi - 0.3, 0.3 + math.pi),
    (1.0, 2.0, math.pi - 0.6, 2.0 + math.pi + 0.2),
    (0.4, 0.1, math.pi - 0.2, 0.1),
    (math.pi - 0.4, 0.5, math.pi - 0.5, 0.5 + math.pi),
    (math.pi - 0.3, 1.0, 0.5, 1.0 + math.pi),
    (math.pi - 0.2, 1.5, 1.1, 1.5 + math.pi + 0.1),
    (math.pi - 1.3, 0.4, 0.3, 0.4 + math.pi + 0.2),
]


def point_rows(bsdf_dict, pairs=PAIRS):
    """For each pair: the text "wo_x wo_y wo_z wi_x wi_y wi_z eval_r eval_g eval_b pdf"."""
    bsdf = mi.load_dict(bsdf_dict)
    ctx = mi.BSDFContext()
    for to, po, ti, pi in pairs:
        wo, wi = direction(to, po), direction(ti, pi)
        si = mi.SurfaceInteraction3f()
        si.wi = mi.Vector3f(wo)
        value = bsdf.eval(ctx, si, mi.Vector3f(wi))
        pdf = bsdf.pdf(ctx, si, mi.Vector3f(wi))
        dirs = " ".join(f"{x:.9g}" for x in wo + wi)
        vals = " ".join(f"{float(value[c]):.9g}" for c in range(3))
        yield f"{dirs} {vals} {float(pdf):.9g}"


def albedo(bsdf_dict, cos_theta_o, seed, samples=1 << 20, energy=True):
    """The mean of sample()'s weight for wo = (sin t cos 30deg, sin t sin 30deg, cos t) and its
    standard error, per channel, from `samples` independent samples. energy: times eta^2 (the
    1 / eta^2 of a refraction undone)."""
    bsdf = mi.load_dict(bsdf_dict)
    sampler = mi.load_dict({"type": "independent"})
    sampler.seed(seed, samples)
    si = dr.zeros(mi.SurfaceInteraction3f)
    sin_theta = math.sqrt(max(0.0, 1.0 - cos_theta_o * cos_theta_o))
    # phi = 30 degrees, so that anisotropic rows depend on both alphas.
    si.wi = mi.Vector3f(sin_theta * math.cos(math.pi / 6), sin_theta * math.sin(math.pi / 6),
                        cos_theta_o)
    bs, weight = bsdf.sample(mi.BSDFContext(), si, sampler.next_1d(), sampler.next_2d())
    out = []
    for c in range(3):
        w = weight[c] * dr.square(bs.eta) if energy else weight[c]
        mean = float(dr.mean(w)[0])
        var = float(dr.mean(dr.square(w - mean))[0])
        out.append((mean, math.sqrt(var / samples)))
    return out
