#include "render/light/light_bounds.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

namespace tessera {
namespace {

/// cos and sin of max(0, a - b) from those of angles a and b in [0, pi].
void subtract_clamped(double cos_a, double sin_a, double cos_b, double sin_b, double* cos_out,
                      double* sin_out) {
  if (cos_a >= cos_b) {
    *cos_out = 1;
    *sin_out = 0;
    return;
  }
  *cos_out = cos_a * cos_b + sin_a * sin_b;
  *sin_out = sin_a * cos_b - cos_a * sin_b;
}

double sine_of(double cos) { return std::sqrt(std::max(0.0, 1.0 - cos * cos)); }

}  // namespace

double LightBounds::importance(glm::vec3 p, glm::vec3 n) const {
  if (infinite) return phi;
  const glm::dvec3 d = glm::dvec3(p) - glm::dvec3(center);
  const double d2 = glm::dot(d, d), r = double(radius);
  // No closer than the bounding sphere (or a hair, for a point light on p): the estimate stays
  // finite.
  const double d2_clamped = std::max({d2, r * r, 1e-20});
  if (d2 <= r * r) return phi / d2_clamped;  // inside the bounds: no angle to bound
  const double dist = std::sqrt(d2);
  const glm::dvec3 wi = d / dist;  // from the light towards p
  // theta_b: the half-angle the bounding sphere subtends at p.
  const double sin_b = r / dist, cos_b = sine_of(sin_b);

  // At the light: the smallest angle between a normal and a direction to p, beyond which the
  // light does not emit.
  double cos_w = glm::dot(glm::dvec3(w), wi);
  if (two_sided) cos_w = std::abs(cos_w);
  const double cos_o = double(cos_theta_o);
  double cos_x, sin_x, cos_light, sin_light;
  subtract_clamped(cos_w, sine_of(cos_w), cos_o, sine_of(cos_o), &cos_x, &sin_x);
  subtract_clamped(cos_x, sin_x, cos_b, sin_b, &cos_light, &sin_light);
  if (cos_light <= double(cos_theta_e)) return 0;
  double result = phi * cos_light / d2_clamped;

  // At p: the smallest angle between its normal (either side) and a direction to the light.
  if (n != glm::vec3(0.0f)) {
    const double cos_i = std::abs(glm::dot(glm::dvec3(n), wi));
    double cos_at_p, sin_at_p;
    subtract_clamped(cos_i, sine_of(cos_i), cos_b, sin_b, &cos_at_p, &sin_at_p);
    result *= std::max(cos_at_p, 1e-3);
  }
  return result;
}

}  // namespace tessera
