// What the light picker knows of a light before sampling it: where it is, how much it emits and
// where it faces (pbrt-v4's LightBounds, with a bounding sphere for the box).
#pragma once

#include <glm/vec3.hpp>

namespace tessera {

/// Bounds of one light, from the scene alone. Every direction in which the light emits lies
/// within theta_e of a normal, and every normal within theta_o of w.
struct LightBounds {
  glm::vec3 center{0.0f};  ///< bounding sphere of the emitting points
  float radius = 0;        ///< >= 0; 0 for a point
  /// Power (luminance-weighted W, >= 0); for a light at infinity the importance itself.
  double phi = 0;
  glm::vec3 w{0.0f, 0.0f, 1.0f};  ///< unit axis of the normal cone
  float cos_theta_o = -1;         ///< -1: normals in every direction (spheres, points)
  float cos_theta_e = 0;          ///< 0: a surface emitting into its hemisphere
  bool two_sided = false;         ///< emits on both sides of every normal
  bool infinite = false;          ///< directional and environment lights

  /// How much the light may give the point p with unit normal n (n == 0: a point in a medium):
  /// phi / d^2 (d from the centre, at least the radius) times bounds of the cosine at the
  /// light and at p over the directions the bounding sphere subtends, as pbrt-v4's
  /// LightBounds::Importance; `phi` for a light at infinity. 0 only where no point of the
  /// bounding sphere emits towards p; the cosine at p (|cos|, both sides, for transmission)
  /// counts at least 1e-3, so that shading normals and transmission can never leave a light
  /// that reaches p without a chance.
  double importance(glm::vec3 p, glm::vec3 n) const;
};

}  // namespace tessera
