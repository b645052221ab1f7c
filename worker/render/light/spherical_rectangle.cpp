#include "render/light/spherical_rectangle.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <glm/geometric.hpp>

#include "render/sampling/warp.h"

namespace tessera {
namespace {

/// a b, written out: std::complex's operator* checks for infinities and NaN through a libgcc
/// call.
std::complex<double> multiply(std::complex<double> a, std::complex<double> b) {
  return {a.real() * b.real() - a.imag() * b.imag(), a.real() * b.imag() + a.imag() * b.real()};
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

  // The paper's normals of the planes through ref and each edge, n0 (edge y0), n1 (x1),
  // n2 (y1), n3 (x0), have closed forms in these coordinates (n0 ~ (0, z0, -y0),
  // n1 ~ (-z0, 0, x1), n2 ~ (0, -z0, y1), n3 ~ (z0, 0, -x0)), and so have the internal angles
  // gamma_i between -n_i and n_(i+1): the angle of the complex number (signed x y of a corner,
  // |z0| times its distance). Their sum is multiplied out as complex numbers, so that one
  // atan2 gives the solid angle sum - 2 pi and no angle needs acos (inaccurate near 0 and pi).
  const double z2 = z0_ * z0_, az = -z0_;
  const auto unit = [](double re, double im) {
    const double norm = std::sqrt(re * re + im * im);
    return std::complex<double>(re / norm, im / norm);
  };
  const std::complex<double> e0 = unit(x1_ * y0_, az * std::sqrt(x1_ * x1_ + y0_ * y0_ + z2));
  const std::complex<double> e1 = unit(-x1_ * y1_, az * std::sqrt(x1_ * x1_ + y1_ * y1_ + z2));
  const std::complex<double> e2 = unit(x0_ * y1_, az * std::sqrt(x0_ * x0_ + y1_ * y1_ + z2));
  const std::complex<double> e3 = unit(-x0_ * y0_, az * std::sqrt(x0_ * x0_ + y0_ * y0_ + z2));
  // Each gamma is in (0, pi) and the solid angle in [0, 2 pi]: the product's angle is the
  // solid angle up to 2 pi, negative only when the solid angle exceeds pi.
  double angle = std::arg(multiply(multiply(e0, e1), multiply(e2, e3)));
  if (angle < 0) angle += 2.0 * kPiD;
  solid_angle_ = angle;
  // e^(i k) = e^(-i gamma_2) e^(-i gamma_3) (2 pi drops out).
  const std::complex<double> ek = std::conj(multiply(e2, e3));
  cos_k_ = ek.real();
  sin_k_ = ek.imag();
  b0_ = -y0_ / std::sqrt(z2 + y0_ * y0_);
  b1_ = y1_ / std::sqrt(z2 + y1_ * y1_);
}

glm::dvec2 SphericalRectangle::sample(glm::vec2 u) const {
  // u.x picks the x coordinate xu by the solid angle left of it (the paper's equations 8-9),
  // u.y the y coordinate along the segment at xu, uniform in the sine of its elevation.
  // au = u S + k, through its cosine and sine: cos(u S) and sin(u S) turned by k.
  const double us = double(u.x) * solid_angle_;
  const double cos_us = std::cos(us), sin_us = std::sin(us);
  const double cos_au = cos_us * cos_k_ - sin_us * sin_k_;
  const double sin_au = sin_us * cos_k_ + cos_us * sin_k_;
  const double fu = (cos_au * b0_ - b1_) / sin_au;
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
