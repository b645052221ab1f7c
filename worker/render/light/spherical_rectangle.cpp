#include "render/light/spherical_rectangle.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

namespace tessera {
namespace {

constexpr double kPiD = 3.14159265358979323846;

/// The angle between unit vectors a and b, accurate near 0 and pi too (where acos of the dot
/// product is not).
double angle_between(glm::dvec3 a, glm::dvec3 b) {
  if (glm::dot(a, b) < 0) return kPiD - 2.0 * std::asin(std::min(1.0, glm::length(a + b) / 2.0));
  return 2.0 * std::asin(std::min(1.0, glm::length(b - a) / 2.0));
}

}  // namespace

SphericalRectangle::SphericalRectangle(glm::dvec3 ref, glm::dvec3 corner, glm::dvec3 ex,
                                       glm::dvec3 ey) {
  // The local frame: x along ex, y along ey, z along the plane's normal turned so that the
  // rectangle lies at z = z0 <= 0 (the paper's convention). Only local coordinates are used
  // from here on, so the turn's handedness does not matter.
  const double exl = glm::length(ex), eyl = glm::length(ey);
  const glm::dvec3 x = ex / exl, y = ey / eyl, z = glm::cross(x, y);
  const glm::dvec3 d = corner - ref;
  x0_ = glm::dot(d, x);
  y0_ = glm::dot(d, y);
  z0_ = -std::abs(glm::dot(d, z));
  x1_ = x0_ + exl;
  y1_ = y0_ + eyl;
  if (!(z0_ < 0)) return;  // in the plane: no solid angle

  const glm::dvec3 v00(x0_, y0_, z0_), v01(x0_, y1_, z0_), v10(x1_, y0_, z0_), v11(x1_, y1_, z0_);
  const glm::dvec3 n0 = glm::normalize(glm::cross(v00, v10));
  const glm::dvec3 n1 = glm::normalize(glm::cross(v10, v11));
  const glm::dvec3 n2 = glm::normalize(glm::cross(v11, v01));
  const glm::dvec3 n3 = glm::normalize(glm::cross(v01, v00));
  const double g0 = angle_between(-n0, n1), g1 = angle_between(-n1, n2);
  const double g2 = angle_between(-n2, n3), g3 = angle_between(-n3, n0);
  b0_ = n0.z;
  b1_ = n2.z;
  k_ = 2.0 * kPiD - g2 - g3;
  solid_angle_ = std::max(0.0, g0 + g1 - k_);
}

glm::dvec2 SphericalRectangle::sample(glm::vec2 u) const {
  // u.x picks the x coordinate xu by the solid angle left of it (the paper's equations 8-9),
  // u.y the y coordinate along the segment at xu, uniform in the sine of its elevation.
  const double au = double(u.x) * solid_angle_ + k_;
  const double fu = (std::cos(au) * b0_ - b1_) / std::sin(au);
  double cu = std::copysign(1.0, fu) / std::sqrt(fu * fu + b0_ * b0_);
  cu = std::clamp(cu, -1.0 + 1e-15, 1.0 - 1e-15);
  double xu = -(cu * z0_) / std::sqrt(1.0 - cu * cu);
  xu = std::isnan(xu) ? x0_ : std::clamp(xu, x0_, x1_);

  const double d2 = xu * xu + z0_ * z0_;
  const double h0 = y0_ / std::sqrt(d2 + y0_ * y0_);
  const double h1 = y1_ / std::sqrt(d2 + y1_ * y1_);
  const double hv = h0 + double(u.y) * (h1 - h0);
  const double hv2 = hv * hv;
  double yv = hv2 < 1.0 - 1e-12 ? hv * std::sqrt(d2) / std::sqrt(1.0 - hv2) : y1_;
  yv = std::isnan(yv) ? y0_ : std::clamp(yv, y0_, y1_);

  const double a = (xu - x0_) / (x1_ - x0_), b = (yv - y0_) / (y1_ - y0_);
  return {std::clamp(a, 0.0, 1.0), std::clamp(b, 0.0, 1.0)};
}

}  // namespace tessera
