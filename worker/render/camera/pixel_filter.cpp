#include "render/camera/pixel_filter.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "render/sampling/warp.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

/// Segments of a tabulated filter over [-radius, radius]. The density is linear between
/// nodes, so it departs from the filter by at most f'' dx^2 / 8: for Mitsuba's default
/// gaussian (stddev 0.5, radius 2, dx = 4 / 1024) that is 2e-6 of the peak density, for
/// lanczos with 4 lobes (|f''| <= pi^2 (1 + 1/16) / 3, dx = 8 / 1024) 2.7e-5, below the 1e-4
/// the sampled offsets must match; lanczos with more lobes gets kTableSegments per 4 of them.
constexpr int kTableSegments = 1024;

/// e^x for x <= 0 with plain IEEE arithmetic only (+, *, /), so that the tabulated filter has
/// the same bits on every machine: glibc's exp picks an implementation by CPU (FMA or not) and
/// is not guaranteed to round alike everywhere. x is halved until it is small, a Taylor series
/// of 14 terms gives e^(x / 2^m) to double precision, and m squarings undo the halving (relative
/// error about 2^m ulp: 1e-13 for the exponents of a filter).
double exp_plain(double x) {
  int halvings = 0;
  while (x < -0.01) {
    x *= 0.5;
    ++halvings;
  }
  double term = 1, sum = 1;
  for (int k = 1; k <= 14; ++k) {
    term = term * x / double(k);
    sum += term;
  }
  for (int i = 0; i < halvings; ++i) sum *= sum;
  return sum;
}

/// sin(pi t) with plain IEEE arithmetic only, as exp_plain and for the same reason (glibc's
/// sin differs between its FMA and SSE2 builds): t is reduced to [0, 1/2] by exact steps
/// (sin(pi t) has period 2, is odd, and sin(pi (1 - t)) = sin(pi t)), then a Taylor series of
/// 13 terms, whose remainder at pi/2 is below 1e-20.
double sin_pi_plain(double t) {
  double sign = 1;
  if (t < 0) {
    t = -t;
    sign = -1;
  }
  t -= 2 * std::floor(t / 2);
  if (t >= 1) {
    t -= 1;
    sign = -sign;
  }
  if (t > 0.5) t = 1 - t;
  const double x = kPiD * t, x2 = x * x;
  double term = x, sum = x;
  for (int k = 1; k <= 12; ++k) {
    term *= -x2 / double((2 * k) * (2 * k + 1));
    sum += term;
  }
  return sign * sum;
}

void check_finite(double v, const char* key) {
  if (!std::isfinite(v)) {
    throw SceneError(std::string("film.filter.") + key + ": must be finite, got " + std::to_string(v));
  }
}

void check_positive(double v, const char* key) {
  if (!(std::isfinite(v) && v > 0)) {
    throw SceneError(std::string("film.filter.") + key + ": must be finite and > 0, got " +
                     std::to_string(v));
  }
}

}  // namespace

double PixelFilterSampler::profile(const PixelFilter& filter, double x) {
  const double ax = std::abs(x);
  if (ax > filter.radius) return 0;
  switch (filter.kind) {
    case FilterKind::box:
      return 1;
    case FilterKind::tent:
      return std::max(0.0, 1 - ax / filter.radius);
    case FilterKind::gaussian: {
      const double alpha = -1 / (2 * filter.stddev * filter.stddev);
      return std::max(0.0,
                      exp_plain(alpha * x * x) - exp_plain(alpha * filter.radius * filter.radius));
    }
    case FilterKind::mitchell: {
      // Mitchell and Netravali's cubic (Mitsuba's rfilters/mitchell.cpp), zero from |x| = 2.
      const double b = filter.b, c = filter.c, x2 = ax * ax, x3 = x2 * ax;
      if (ax < 1) return ((12 - 9 * b - 6 * c) * x3 + (-18 + 12 * b + 6 * c) * x2 + (6 - 2 * b)) / 6;
      if (ax < 2) {
        return ((-b - 6 * c) * x3 + (6 * b + 30 * c) * x2 + (-12 * b - 48 * c) * ax + (8 * b + 24 * c)) / 6;
      }
      return 0;
    }
    case FilterKind::lanczos: {
      // sinc(x) sinc(x / lobes), 1 at 0 (Mitsuba's rfilters/lanczos.cpp); radius = lobes.
      if (ax < 1e-7) return 1;
      const double x1 = kPiD * ax, x2 = x1 / filter.radius;
      return sin_pi_plain(ax) * sin_pi_plain(ax / filter.radius) / (x1 * x2);
    }
  }
  return 0;
}

PixelFilterSampler::PixelFilterSampler(const PixelFilter& filter) : filter_(filter) {
  check_positive(filter.radius, "radius");
  switch (filter.kind) {
    case FilterKind::box:
    case FilterKind::tent:
      return;  // sampled in closed form
    case FilterKind::gaussian:
      check_positive(filter.stddev, "stddev");
      break;
    case FilterKind::mitchell:
      check_finite(filter.b, "b");
      check_finite(filter.c, "c");
      break;
    case FilterKind::lanczos:
      break;
  }

  // Tabulate the profile at the nodes; the filter between two nodes is their linear
  // interpolation, whose integral over a segment is the trapezoid (exact, not an estimate).
  const double r = filter.radius;
  const int segments =
      filter.kind == FilterKind::lanczos ? kTableSegments * int(std::ceil(r / 4)) : kTableSegments;
  dx_ = 2 * r / segments;
  value_.resize(size_t(segments) + 1);
  pdf_.resize(size_t(segments) + 1);
  for (int i = 0; i <= segments; ++i) {
    value_[size_t(i)] = profile(filter, -r + dx_ * i);
    pdf_[size_t(i)] = std::abs(value_[size_t(i)]);
    signed_ = signed_ || value_[size_t(i)] < 0;
  }
  double integral = 0, signed_integral = 0;
  for (int i = 0; i < segments; ++i) {
    integral += 0.5 * (pdf_[size_t(i)] + pdf_[size_t(i) + 1]) * dx_;
    signed_integral += 0.5 * (value_[size_t(i)] + value_[size_t(i) + 1]) * dx_;
  }
  if (!(integral > 0)) throw SceneError("film.filter: the filter's footprint has no weight");
  if (!(signed_integral > 0)) {
    throw SceneError("film.filter: the filter integrates to " + std::to_string(signed_integral) +
                     " (its negative lobes outweigh the rest), so it cannot be normalised");
  }
  for (double& p : pdf_) p /= integral;
  for (double& v : value_) v /= signed_integral;
  cdf_.resize(size_t(segments) + 1);
  cdf_[0] = 0;
  for (int i = 0; i < segments; ++i) {
    cdf_[size_t(i) + 1] = cdf_[size_t(i)] + 0.5 * (pdf_[size_t(i)] + pdf_[size_t(i) + 1]) * dx_;
  }
  cdf_.back() = 1;  // the sum is 1 up to rounding; make the last segment absorb it
}

double PixelFilterSampler::sample_table(double u, double* weight) const {
  // The segment [x_i, x_i+1) whose cumulative weight brackets u.
  const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
  const size_t i = size_t(std::clamp<ptrdiff_t>(it - cdf_.begin() - 1, 0, ptrdiff_t(cdf_.size()) - 2));
  // Within it the density is p0 + (p1 - p0) t (t in [0, 1]); its integral from 0 to t is
  // a t^2 + b t. Solve a t^2 + b t = du with the form that does not cancel (b >= 0).
  const double du = u - cdf_[i];
  const double a = 0.5 * (pdf_[i + 1] - pdf_[i]) * dx_, b = pdf_[i] * dx_;
  const double disc = std::max(0.0, b * b + 4 * a * du);
  const double denom = b + std::sqrt(disc);
  const double t = denom > 0 ? std::clamp(2 * du / denom, 0.0, 1.0) : 0.0;
  if (weight) {
    // f(x) / (pdf(x) integral f): both linear in the segment, so their ratio is the segment's
    // sign times integral |f| / integral f where f keeps its sign there, and the ratio of the
    // two interpolations where it changes sign (both ends non-zero, so pdf > 0 inside).
    const double v0 = value_[i], v1 = value_[i + 1];
    if (v0 * v1 < 0) {
      *weight = (v0 + (v1 - v0) * t) / (pdf_[i] + (pdf_[i + 1] - pdf_[i]) * t);
    } else {
      const double mass = pdf_[i] + pdf_[i + 1];
      const double magnitude = mass > 0 ? (std::abs(v0) + std::abs(v1)) / mass : 0.0;
      *weight = (v0 < 0 || v1 < 0) ? -magnitude : magnitude;
    }
  }
  return -filter_.radius + dx_ * (double(i) + t);
}

double PixelFilterSampler::sample_1d(double u, double* weight) const {
  const double r = filter_.radius;
  switch (filter_.kind) {
    case FilterKind::box:
      if (weight) *weight = 1;
      return (2 * u - 1) * r;
    case FilterKind::tent:
      // Inverse of the tent's cumulative distribution, (1 + x/r)^2 / 2 on [-r, 0].
      if (weight) *weight = 1;
      return u < 0.5 ? r * (std::sqrt(2 * u) - 1) : r * (1 - std::sqrt(2 - 2 * u));
    case FilterKind::gaussian:
    case FilterKind::mitchell:
    case FilterKind::lanczos:
      return sample_table(u, weight);
  }
  return 0;
}

glm::vec2 PixelFilterSampler::sample(glm::vec2 u) const {
  return {float(sample_1d(double(u.x))), float(sample_1d(double(u.y)))};
}

glm::vec2 PixelFilterSampler::film_position(int x, int y, glm::vec2 u) const {
  if (filter_.kind == FilterKind::box && filter_.radius == 0.5) {
    return {float(x) + u.x, float(y) + u.y};
  }
  const glm::vec2 d = sample(u);
  return {float(x) + 0.5f + d.x, float(y) + 0.5f + d.y};
}

FilmSample PixelFilterSampler::film_sample(int x, int y, glm::vec2 u) const {
  if (!signed_) return {film_position(x, y, u), 1.0};
  double wx = 1, wy = 1;
  const float dx = float(sample_1d(double(u.x), &wx)), dy = float(sample_1d(double(u.y), &wy));
  return {{float(x) + 0.5f + dx, float(y) + 0.5f + dy}, wx * wy};
}

}  // namespace tessera
