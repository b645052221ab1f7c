// The solid angle a rectangle subtends at a point, and points on the rectangle whose directions
// from that point are uniform in it (Urena, Fajardo, King, "An Area-Preserving Parametrization
// for Spherical Rectangles", EGSR 2013; pbrt-v4 samples rectangular bilinear patches so).
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace tessera {

/// The rectangle corner + a ex + b ey, (a, b) in [0, 1]^2, seen from a reference point.
/// Computed in double: the solid angle is a sum of four angles minus 2 pi, which loses to
/// cancellation what float cannot spare when the rectangle looks small.
class SphericalRectangle {
 public:
  /// ex and ey must be orthogonal and non-zero.
  SphericalRectangle(glm::dvec3 ref, glm::dvec3 corner, glm::dvec3 ex, glm::dvec3 ey);

  /// Distance from the reference point to the rectangle's plane (>= 0).
  double plane_distance() const { return -z0_; }
  /// The solid angle (sr) the rectangle subtends; 0 when the point lies in its plane. Taken
  /// modulo 2 pi from the product of the internal angles' unit complex numbers, so it is exact
  /// to about 1e-15 sr but must not be asked within that of 0 or 2 pi (a point a hair off the
  /// plane: AreaLight keeps 1e-5 of the diagonal away).
  double solid_angle() const { return solid_angle_; }

  /// The (a, b) in [0, 1]^2 of the point whose direction from the reference point is
  /// uniform in the solid angle (density 1 / solid_angle()), from u in [0, 1)^2. Accurate when
  /// plane_distance() is not tiny against the rectangle's size (the caller decides: the map
  /// degenerates as the point approaches the plane).
  glm::dvec2 sample(glm::vec2 u) const;

 private:
  double x0_ = 0, x1_ = 0, y0_ = 0, y1_ = 0, z0_ = 0;  ///< the rectangle in the local frame
  double b0_ = 0, b1_ = 0;  ///< z of the normals of the planes through the edges y0 and y1
  /// cos and sin of k = 2 pi - gamma_2 - gamma_3, the paper's offset of the swept angle
  double cos_k_ = 1, sin_k_ = 0;
  double solid_angle_ = 0;
};

}  // namespace tessera
