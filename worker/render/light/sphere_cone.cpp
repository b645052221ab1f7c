#include "render/light/sphere_cone.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "render/sampling/warp.h"

namespace tessera {
namespace {
/// Frame's basis (Duff et al. 2017) in double: s and t orthogonal to the unit vector n.
void orthonormal_basis(glm::dvec3 n, glm::dvec3* s, glm::dvec3* t) {
  const double sign = std::copysign(1.0, n.z);
  const double a = -1.0 / (sign + n.z);
  const double b = n.x * n.y * a;
  *s = {1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x};
  *t = {b, sign + n.y * n.y * a, -n.y};
}

}  // namespace

SphereCone::SphereCone(glm::dvec3 ref, glm::dvec3 center, double radius) {
  const glm::dvec3 to_center = center - ref;
  const double dist2 = glm::dot(to_center, to_center);
  axis_ = to_center / std::sqrt(dist2);
  sin2_max_ = std::min(1.0, radius * radius / dist2);
  // 1 - cos = sin^2 / (1 + cos): no cancellation for small cones.
  one_minus_cos_ = sin2_max_ / (1.0 + std::sqrt(1.0 - sin2_max_));
}

double SphereCone::solid_angle() const { return 2.0 * kPiD * one_minus_cos_; }

glm::dvec3 SphereCone::sample_normal(glm::vec2 u) const {
  // theta uniform in cos over the cap, as 1 - cos theta = u (1 - cos theta_max).
  const double one_minus_cos_theta = double(u.x) * one_minus_cos_;
  const double cos_theta = 1.0 - one_minus_cos_theta;
  const double sin2_theta = one_minus_cos_theta * (2.0 - one_minus_cos_theta);
  // alpha: the angle at the centre between the direction back to ref and the point where the
  // ray at theta first meets the sphere (law of sines in the triangle ref, centre, point).
  const double sin_max = std::sqrt(sin2_max_);
  const double cos_alpha = sin2_theta / sin_max +
                           cos_theta * std::sqrt(std::max(0.0, 1.0 - sin2_theta / sin2_max_));
  const double sin_alpha = std::sqrt(std::max(0.0, 1.0 - cos_alpha * cos_alpha));
  const double phi = 2.0 * kPiD * double(u.y);
  // In the frame whose z is the axis, the normal points back towards ref: -z at alpha = 0.
  glm::dvec3 s, t;
  orthonormal_basis(axis_, &s, &t);
  return sin_alpha * std::cos(phi) * s + sin_alpha * std::sin(phi) * t - cos_alpha * axis_;
}

}  // namespace tessera
