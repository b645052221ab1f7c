#include "shading_normal.h"

#include <cmath>

#include <glm/geometric.hpp>

#include "render/frame.h"

namespace tessera {
namespace {

/// v / |v|, or nothing usable (returns false) when v has no finite non-zero length.
bool normalize_checked(glm::vec3 v, glm::vec3* out) {
  const float len = glm::length(v);
  if (!(len > 0) || !std::isfinite(len)) return false;
  *out = v / len;
  return true;
}

}  // namespace

glm::vec3 shading_tangent(glm::vec3 dpdu, glm::vec3 ns) {
  // A tangent part below 1e-5 of dpdu is rounding noise of a dpdu (nearly) along ns: its
  // direction would be arbitrary.
  const glm::vec3 tangential = dpdu - ns * glm::dot(ns, dpdu);
  glm::vec3 s;
  if (glm::length(tangential) > 1e-5f * glm::length(dpdu) && normalize_checked(tangential, &s)) return s;
  return Frame(ns).s;
}

glm::vec3 normal_mapped(glm::vec3 texel_rgb, glm::vec3 dpdu, glm::vec3 /*dpdv*/, glm::vec3 ns) {
  glm::vec3 local;
  if (!normalize_checked(texel_rgb * 2.0f - 1.0f, &local)) return ns;
  const glm::vec3 s = shading_tangent(dpdu, ns);
  const glm::vec3 t = glm::cross(ns, s);
  glm::vec3 n;
  if (!normalize_checked(s * local.x + t * local.y + ns * local.z, &n)) return ns;
  return n;
}

glm::vec3 bump_mapped(glm::vec2 height_gradient, float scale, glm::vec3 dpdu, glm::vec3 dpdv,
                      glm::vec3 ns, glm::vec3 ng) {
  const glm::vec2 g = height_gradient * scale;
  const glm::vec3 dpdu_b = dpdu + ns * (g.x - glm::dot(ns, dpdu));
  const glm::vec3 dpdv_b = dpdv + ns * (g.y - glm::dot(ns, dpdv));
  glm::vec3 n;
  if (!normalize_checked(glm::cross(dpdu_b, dpdv_b), &n)) return ns;
  return glm::dot(ng, n) < 0 ? -n : n;
}

}  // namespace tessera
