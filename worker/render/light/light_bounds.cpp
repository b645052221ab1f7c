#include "render/light/light_bounds.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

namespace tessera {
namespace {

double sine_of(double cos) { return std::sqrt(std::max(0.0, 1.0 - cos * cos)); }

/// cos(max(0, a - b)) from cos a and cos b (angles in [0, pi]), sin b given; sin a only
/// computed when needed.
double cos_subtract_clamped(double cos_a, double cos_b, double sin_b) {
  if (cos_a >= cos_b) return 1;
  return cos_a * cos_b + sine_of(cos_a) * sin_b;
}

}  // namespace

double LightBounds::importance(glm::vec3 p, glm::vec3 n) const {
  if (infinite) return phi;
  const glm::dvec3 d = glm::dvec3(p) - glm::dvec3(center);
  const double d2 = glm::dot(d, d), r = double(radius), r2 = r * r;
  // Inside the bounds there is no angle to bound; the distance counts as the radius (or a
  // hair, for a point light on p), so the estimate stays finite.
  if (d2 <= r2) return phi / std::max(r2, 1e-20);
  const double inv_dist = 1.0 / std::sqrt(d2);
  // theta_b: the half-angle the bounding sphere subtends at p.
  const double sin_b = r * inv_dist, cos_b = std::sqrt(d2 - r2) * inv_dist;

  // At the light: the smallest angle between a normal (within theta_o of w) and a direction
  // to p (within theta_b of d), beyond which (theta_e) the light does not emit.
  double cos_w = glm::dot(glm::dvec3(w), d) * inv_dist;
  if (two_sided) cos_w = std::abs(cos_w);
  const double cos_o = double(cos_theta_o);
  double cos_x = 1, sin_x = 0;  // theta_x = max(0, theta_w - theta_o)
  if (cos_w < cos_o) {
    const double sin_w = sine_of(cos_w), sin_o = sine_of(cos_o);
    cos_x = cos_w * cos_o + sin_w * sin_o;
    sin_x = sin_w * cos_o - cos_w * sin_o;
  }
  const double cos_light = cos_x >= cos_b ? 1.0 : cos_x * cos_b + sin_x * sin_b;
  if (cos_light <= double(cos_theta_e)) return 0;
  double result = phi * cos_light / std::max(d2, 1e-20);

  // At p: the smallest angle between its normal (either side) and a direction to the light.
  if (n != glm::vec3(0.0f)) {
    const double cos_i = std::abs(glm::dot(glm::dvec3(n), d)) * inv_dist;
    result *= std::max(cos_subtract_clamped(cos_i, cos_b, sin_b), 1e-3);
  }
  return result;
}

}  // namespace tessera
