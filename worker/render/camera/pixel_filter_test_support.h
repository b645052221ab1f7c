// The filters of the pixel filter tests and their profiles and moments from the definitions
// (libm, Simpson's rule), independent of PixelFilterSampler's own arithmetic.
#pragma once

#include <algorithm>
#include <cmath>

#include "render/camera/pixel_filter.h"
#include "scene/scene.h"

namespace tessera::pixel_filter_test {

inline PixelFilter box() { return {FilterKind::box, 0.5, 0.5}; }
inline PixelFilter tent() { return {FilterKind::tent, 1.0, 0.5}; }
inline PixelFilter gaussian(double stddev = 0.5) { return {FilterKind::gaussian, 4 * stddev, stddev}; }
inline PixelFilter mitchell(double b = 1.0 / 3, double c = 1.0 / 3) { return {FilterKind::mitchell, 2.0, 0.5, b, c}; }
inline PixelFilter catmullrom() { return mitchell(0, 0.5); }
inline PixelFilter lanczos(int lobes = 3) { return {FilterKind::lanczos, double(lobes), 0.5}; }

/// The filter's profile from its definition with libm's exp (independent of the sampler's own
/// arithmetic).
inline double reference_profile(const PixelFilter& f, double x) {
  const double ax = std::abs(x);
  if (ax > f.radius) return 0;
  switch (f.kind) {
    case FilterKind::box:
      return 1;
    case FilterKind::tent:
      return 1 - ax / f.radius;
    case FilterKind::gaussian: {
      const double a = -1 / (2 * f.stddev * f.stddev);
      return std::max(0.0, std::exp(a * x * x) - std::exp(a * f.radius * f.radius));
    }
    case FilterKind::mitchell: {
      // Mitchell and Netravali (1988), eq. 8, with B and C.
      const double b = f.b, c = f.c;
      if (ax < 1) return ((12 - 9 * b - 6 * c) * std::pow(ax, 3) + (-18 + 12 * b + 6 * c) * ax * ax + 6 - 2 * b) / 6;
      if (ax < 2) {
        return ((-b - 6 * c) * std::pow(ax, 3) + (6 * b + 30 * c) * ax * ax + (-12 * b - 48 * c) * ax + 8 * b + 24 * c) /
               6;
      }
      return 0;
    }
    case FilterKind::lanczos: {
      if (ax == 0) return 1;
      const double pi = 3.14159265358979323846;
      return std::sin(pi * ax) / (pi * ax) * std::sin(pi * ax / f.radius) / (pi * ax / f.radius);
    }
  }
  return 0;
}

/// Integral of x^k f(x) (|f(x)| with `absolute`) over [lo, hi] by Simpson's rule on n (even)
/// intervals.
inline double integrate(const PixelFilter& f, double lo, double hi, int k, int n = 20000, bool absolute = false) {
  const double h = (hi - lo) / n;
  double sum = 0;
  for (int i = 0; i <= n; ++i) {
    const double x = lo + h * i;
    const double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
    const double v = reference_profile(f, x);
    sum += w * std::pow(x, k) * (absolute ? std::abs(v) : v);
  }
  return sum * h / 3;
}

}  // namespace tessera::pixel_filter_test
