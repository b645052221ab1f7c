#include "render/light/spherical_rectangle.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

namespace tessera {
namespace {

constexpr double kPiD = 3.14159265358979323846;

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

  // The paper's normals of the planes through ref and each edge, n0 (edge y0), n1 (x1),
  // n2 (y1), n3 (x0), have closed forms in these coordinates (n0 ~ (0, z0, -y0),
  // n1 ~ (-z0, 0, x1), n2 ~ (0, -z0, y1), n3 ~ (z0, 0, -x0)), and so have the internal angles
  // gamma_i between -n_i and n_(i+1): atan2(|z0| |corner|, the corner's signed x y), with no
  // normalisation and no acos (inaccurate near 0 and pi).
  const double z2 = z0_ * z0_, az = -z0_;
  const double r00 = std::sqrt(x0_ * x0_ + y0_ * y0_ + z2), r01 = std::sqrt(x0_ * x0_ + y1_ * y1_ + z2);
  const double r10 = std::sqrt(x1_ * x1_ + y0_ * y0_ + z2), r11 = std::sqrt(x1_ * x1_ + y1_ * y1_ + z2);
  const double g0 = std::atan2(az * r10, x1_ * y0_), g1 = std::atan2(az * r11, -x1_ * y1_);
  const double g2 = std::atan2(az * r01, x0_ * y1_), g3 = std::atan2(az * r00, -x0_ * y0_);
  b0_ = -y0_ / std::sqrt(z2 + y0_ * y0_);
  b1_ = y1_ / std::sqrt(z2 + y1_ * y1_);
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
