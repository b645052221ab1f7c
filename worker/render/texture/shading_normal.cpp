#include "shading_normal.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "render/math/frame.h"

namespace tessera {
namespace {

/// v / |v|, or nothing usable (returns false) when v has no finite non-zero length.
bool normalize_checked(glm::vec3 v, glm::vec3* out) {
  const float len = glm::length(v);
  if (!(len > 0) || !std::isfinite(len)) return false;
  *out = v / len;
  return true;
}

/// The shading frame (s, t, ns) Mitsuba's adapters perturb.
struct ShadingFrame {
  glm::vec3 s, t, n;
  ShadingFrame(glm::vec3 dpdu, glm::vec3 ns)
      : s(shading_tangent(dpdu, ns)), t(glm::cross(ns, s)), n(ns) {}
  glm::vec3 to_local(glm::vec3 v) const { return {glm::dot(v, s), glm::dot(v, t), glm::dot(v, n)}; }
  glm::vec3 to_world(glm::vec3 v) const { return s * v.x + t * v.y + n * v.z; }
};

/// Mitsuba's flip_invalid_normals: m (local to the shading frame) keeps its component along ns
/// and loses the sign of its tangential part when it and ns disagree about wi's side.
glm::vec3 flip_invalid(glm::vec3 m_local, glm::vec3 wi_local) {
  if (wi_local.z * glm::dot(wi_local, m_local) <= 0) return {-m_local.x, -m_local.y, m_local.z};
  return m_local;
}

glm::vec3 normal_mapped_impl(glm::vec3 texel_rgb, glm::vec3 dpdu, glm::vec3 ns,
                             const glm::vec3* wi) {
  const ShadingFrame frame(dpdu, ns);
  glm::vec3 m = texel_rgb * 2.0f - 1.0f;
  if (wi) m = flip_invalid(m, frame.to_local(*wi));
  glm::vec3 local, n;
  if (!normalize_checked(m, &local) || !normalize_checked(frame.to_world(local), &n)) return ns;
  return n;
}

glm::vec3 bump_mapped_impl(glm::vec2 height_gradient, float scale, glm::vec3 dpdu, glm::vec3 dpdv,
                           glm::vec3 ns, glm::vec3 ng, const glm::vec3* wi) {
  const glm::vec2 g = height_gradient * scale;
  const glm::vec3 dpdu_b = dpdu + ns * (g.x - glm::dot(ns, dpdu));
  const glm::vec3 dpdv_b = dpdv + ns * (g.y - glm::dot(ns, dpdv));
  glm::vec3 n;
  if (!normalize_checked(glm::cross(dpdu_b, dpdv_b), &n)) return ns;
  if (glm::dot(ng, n) < 0) n = -n;
  if (!wi) return n;
  const ShadingFrame frame(dpdu, ns);
  return frame.to_world(flip_invalid(frame.to_local(n), frame.to_local(*wi)));
}

}  // namespace

glm::vec3 shading_tangent(glm::vec3 dpdu, glm::vec3 ns) {
  // A tangent part below 1e-5 of dpdu is rounding noise of a dpdu (nearly) along ns: its
  // direction would be arbitrary.
  const glm::vec3 tangential = dpdu - ns * glm::dot(ns, dpdu);
  glm::vec3 s;
  if (glm::length(tangential) > 1e-5f * glm::length(dpdu) && normalize_checked(tangential, &s))
    return s;
  return Frame(ns).s;
}

glm::vec3 normal_mapped(glm::vec3 texel_rgb, glm::vec3 dpdu, glm::vec3 /*dpdv*/, glm::vec3 ns,
                        glm::vec3 wi) {
  return normal_mapped_impl(texel_rgb, dpdu, ns, &wi);
}

glm::vec3 normal_mapped(glm::vec3 texel_rgb, glm::vec3 dpdu, glm::vec3 /*dpdv*/, glm::vec3 ns) {
  return normal_mapped_impl(texel_rgb, dpdu, ns, nullptr);
}

glm::vec3 bump_mapped(glm::vec2 height_gradient, float scale, glm::vec3 dpdu, glm::vec3 dpdv,
                      glm::vec3 ns, glm::vec3 ng, glm::vec3 wi) {
  return bump_mapped_impl(height_gradient, scale, dpdu, dpdv, ns, ng, &wi);
}

glm::vec3 bump_mapped(glm::vec2 height_gradient, float scale, glm::vec3 dpdu, glm::vec3 dpdv,
                      glm::vec3 ns, glm::vec3 ng) {
  return bump_mapped_impl(height_gradient, scale, dpdu, dpdv, ns, ng, nullptr);
}

glm::vec3 perturbed_tangent(glm::vec3 n_perturbed, glm::vec3 s) {
  glm::vec3 t;
  if (normalize_checked(s - n_perturbed * glm::dot(n_perturbed, s), &t)) return t;
  return Frame(n_perturbed).s;
}

float shadow_terminator(glm::vec3 n_perturbed, glm::vec3 ns, glm::vec3 wo) {
  // tan^2 of the angle to ns, as Mitsuba's Frame::tan_theta_2 (infinite at 90 degrees).
  const auto tan2 = [&](glm::vec3 v) {
    const float c = glm::dot(v, ns);
    return std::max(1.0f - c * c, 0.0f) / (c * c);
  };
  const float alpha2 = std::min(0.125f * tan2(n_perturbed), 1.0f);
  if (alpha2 == 0) return 1.0f;  // unperturbed: no shadowing even at grazing wo (0 * inf)
  return 2.0f / (1.0f + std::sqrt(1.0f + alpha2 * tan2(wo)));
}

}  // namespace tessera
