// The cone of directions a sphere subtends from a point outside it, and points on the sphere
// whose directions are uniform in that cone (pbrt-v4's Sphere::Sample(ctx, u); Mitsuba 3's
// sphere emitter samples the same way).
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace tessera {

/// A sphere (centre, radius) seen from a point outside it, in double (the cap's 1 - cos is
/// formed without cancellation, so far and small spheres keep an exact density).
class SphereCone {
 public:
  /// ref must lie outside the sphere: |ref - center| > radius > 0.
  SphereCone(glm::dvec3 ref, glm::dvec3 center, double radius);

  /// The cone's solid angle, 2 pi (1 - cos theta_max) (sr, > 0).
  double solid_angle() const;

  /// The unit outward normal n of the sphere's point center + radius n whose direction from
  /// ref is uniform in the cone (density 1 / solid_angle()), from u in [0, 1)^2. The point is
  /// on the near side (visible from ref).
  glm::dvec3 sample_normal(glm::vec2 u) const;

 private:
  glm::dvec3 axis_;           ///< unit, from ref to the centre
  double sin2_max_ = 0;       ///< sin^2 theta_max = (radius / distance)^2
  double one_minus_cos_ = 0;  ///< 1 - cos theta_max
};

}  // namespace tessera
