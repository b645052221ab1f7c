// Shading normals perturbed by a normal map or a bump map, as Mitsuba's normalmap and bumpmap
// BSDF adapters compute them (src/bsdfs/normalmap.cpp, src/bsdfs/bumpmap.cpp).
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace tessera {

/// The shading frame's tangent Mitsuba builds at a hit (SurfaceInteraction::initialize_sh_frame):
/// dpdu made orthogonal to the unit shading normal ns and normalised; when dpdu is zero (no
/// parametrisation) or (within 1e-5 of its length) parallel to ns, the tangent of the branchless basis around ns (Frame).
glm::vec3 shading_tangent(glm::vec3 dpdu, glm::vec3 ns);

/// Normal from a tangent-space normal map texel, given the frame (dpdu, dpdv, ns), all in world
/// space, ns of unit length. The texel's linear RGB in [0, 1] maps to a direction 2 rgb - 1 in
/// the shading frame (s = shading_tangent(dpdu, ns), t = ns x s, ns): blue along ns, red along
/// the direction of increasing u. dpdv is not used (Mitsuba derives t from ns and s).
/// Returns the unit world-space normal; ns when the texel maps to the zero vector (a map of
/// mid-grey, where Mitsuba would produce NaN).
glm::vec3 normal_mapped(glm::vec3 texel_rgb, glm::vec3 dpdu, glm::vec3 dpdv, glm::vec3 ns);

/// Normal of the surface displaced along ns by scale * height(u, v), given the height's
/// gradient (TextureSet::gradient) and the frame (dpdu, dpdv, ns) in world space:
/// normalize(dpdu' x dpdv') with dpdu' = dpdu + ns (scale dh/du - ns.dpdu) (likewise for v),
/// turned to the side of the geometric normal ng. Returns ns when dpdu' x dpdv' vanishes
/// (no parametrisation).
glm::vec3 bump_mapped(glm::vec2 height_gradient, float scale, glm::vec3 dpdu, glm::vec3 dpdv,
                      glm::vec3 ns, glm::vec3 ng);

/// As above with ns standing for the geometric normal (the interface the integrator was first
/// given): the result then lies on ns's side rather than ng's.
inline glm::vec3 bump_mapped(glm::vec2 height_gradient, float scale, glm::vec3 dpdu, glm::vec3 dpdv,
                             glm::vec3 ns) {
  return bump_mapped(height_gradient, scale, dpdu, dpdv, ns, ns);
}

}  // namespace tessera
