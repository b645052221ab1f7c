// Shading normals perturbed by a normal map or a bump map, and the shadowing term that goes with
// them, as Mitsuba 3.9's normalmap and bumpmap BSDF adapters compute them
// (src/bsdfs/normalmap.cpp, src/bsdfs/bumpmap.cpp, src/bsdfs/normalmap_helpers.h).
//
// How the integrator uses them, as the adapters do: evaluate (and sample) the material with
// n' = normal_mapped(...) or bump_mapped(...) as its shading normal (tangent:
// perturbed_tangent(n', s)); a direction wo counts only when it lies on the same side of n' as
// of the unperturbed shading normal ns (dot(wo, ns) * dot(wo, n') > 0, else the BSDF value and
// pdf are 0); the BSDF value (and a sampled weight) is multiplied by
// shadow_terminator(n', ns, wo), the pdf is not. All vectors are world space; wi and wo point
// away from the surface.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace tessera {

/// The shading frame's tangent Mitsuba builds at a hit (SurfaceInteraction::initialize_sh_frame):
/// dpdu made orthogonal to the unit shading normal ns and normalised; when dpdu is zero (no
/// parametrisation) or (within 1e-5 of its length) parallel to ns, the tangent of the
/// branchless basis around ns (Frame).
glm::vec3 shading_tangent(glm::vec3 dpdu, glm::vec3 ns);

/// Normal from a tangent-space normal map texel (Mitsuba's normalmap), given the frame
/// (dpdu, dpdv, ns) and the direction wi towards the previous vertex. The texel's linear RGB in
/// [0, 1] maps to the direction m = 2 rgb - 1 in the shading frame (s = shading_tangent(dpdu, ns),
/// t = ns x s, ns): blue along ns, red along increasing u. When m and ns disagree about wi's side
/// (sign(wi.ns) (wi.m) <= 0), m's tangential part is negated (Mitsuba's flip_invalid_normals,
/// its default). dpdv is not used (t comes from ns and s). Returns the unit normal; ns when the
/// texel maps to the zero vector (mid-grey, where Mitsuba would produce NaN).
glm::vec3 normal_mapped(glm::vec3 texel_rgb, glm::vec3 dpdu, glm::vec3 dpdv, glm::vec3 ns,
                        glm::vec3 wi);
/// As above without the flip (Mitsuba's flip_invalid_normals = false).
glm::vec3 normal_mapped(glm::vec3 texel_rgb, glm::vec3 dpdu, glm::vec3 dpdv, glm::vec3 ns);

/// Normal of the surface displaced along ns by scale * height(u, v) (Mitsuba's bumpmap), given
/// the height's gradient (TextureSet::gradient), the frame (dpdu, dpdv, ns), the geometric
/// normal ng and wi: normalize(dpdu' x dpdv') with dpdu' = dpdu + ns (scale dh/du - ns.dpdu)
/// (likewise for v), turned to ng's side, then flipped as normal_mapped() flips (tangential part
/// negated in the frame of shading_tangent(dpdu, ns) when it disagrees with ns about wi's side).
/// Returns ns when dpdu' x dpdv' vanishes (no parametrisation).
glm::vec3 bump_mapped(glm::vec2 height_gradient, float scale, glm::vec3 dpdu, glm::vec3 dpdv,
                      glm::vec3 ns, glm::vec3 ng, glm::vec3 wi);
/// As above without the flip (Mitsuba's flip_invalid_normals = false).
glm::vec3 bump_mapped(glm::vec2 height_gradient, float scale, glm::vec3 dpdu, glm::vec3 dpdv,
                      glm::vec3 ns, glm::vec3 ng);

/// The perturbed frame's tangent: the shading tangent s made orthogonal to the perturbed normal
/// n' (Mitsuba's normalmap; it matters only to anisotropic materials).
glm::vec3 perturbed_tangent(glm::vec3 n_perturbed, glm::vec3 s);

/// Microfacet-based shadowing of a perturbed normal (Estevez et al., "A Microfacet-Based
/// Shadowing Function to Solve the Bump Terminator Problem", Ray Tracing Gems 2019), Mitsuba's
/// use_shadowing_function (its default): 2 / (1 + sqrt(1 + a2 tan^2(wo))) with
/// a2 = min(tan^2(n') / 8, 1), both angles measured from ns. 1 for an unperturbed normal or wo
/// along ns; in (0, 1] otherwise. n', ns and wo unit vectors.
float shadow_terminator(glm::vec3 n_perturbed, glm::vec3 ns, glm::vec3 wo);

}  // namespace tessera
