#include "pixel_filter.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "scene/scene_error.h"

namespace tessera {
namespace {

/// Segments of the gaussian's tabulated density over [-radius, radius]. The density is
/// linear between nodes, so it departs from the filter by at most f'' dx^2 / 8: for Mitsuba's
/// default (stddev 0.5, radius 2, dx = 4 / 1024) that is 2e-6 of the peak density, well below
/// the 1e-4 the sampled offsets must match.
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
  }
  return 0;
}

PixelFilterSampler::PixelFilterSampler(const PixelFilter& filter) : filter_(filter) {
  check_positive(filter.radius, "radius");
  if (filter.kind != FilterKind::gaussian) return;
  check_positive(filter.stddev, "stddev");

  // Tabulate the profile at the nodes; the density between two nodes is their linear
  // interpolation, whose integral over a segment is the trapezoid (exact, not an estimate).
  const double r = filter.radius;
  dx_ = 2 * r / kTableSegments;
  pdf_.resize(kTableSegments + 1);
  for (int i = 0; i <= kTableSegments; ++i) pdf_[size_t(i)] = profile(filter, -r + dx_ * i);
  double integral = 0;
  for (int i = 0; i < kTableSegments; ++i)
    integral += 0.5 * (pdf_[size_t(i)] + pdf_[size_t(i) + 1]) * dx_;
  if (!(integral > 0)) throw SceneError("film.filter: the gaussian's footprint has no weight");
  for (double& p : pdf_) p /= integral;
  cdf_.resize(kTableSegments + 1);
  cdf_[0] = 0;
  for (int i = 0; i < kTableSegments; ++i) {
    cdf_[size_t(i) + 1] = cdf_[size_t(i)] + 0.5 * (pdf_[size_t(i)] + pdf_[size_t(i) + 1]) * dx_;
  }
  cdf_.back() = 1;  // the sum is 1 up to rounding; make the last segment absorb it
}

double PixelFilterSampler::sample_table(double u) const {
  // The segment [x_i, x_i+1) whose cumulative weight brackets u.
  const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
  const size_t i = size_t(std::clamp<ptrdiff_t>(it - cdf_.begin() - 1, 0, kTableSegments - 1));
  // Within it the density is p0 + (p1 - p0) t (t in [0, 1]); its integral from 0 to t is
  // a t^2 + b t. Solve a t^2 + b t = du with the form that does not cancel (b >= 0).
  const double du = u - cdf_[i];
  const double a = 0.5 * (pdf_[i + 1] - pdf_[i]) * dx_, b = pdf_[i] * dx_;
  const double disc = std::max(0.0, b * b + 4 * a * du);
  const double denom = b + std::sqrt(disc);
  const double t = denom > 0 ? std::clamp(2 * du / denom, 0.0, 1.0) : 0.0;
  return -filter_.radius + dx_ * (double(i) + t);
}

double PixelFilterSampler::sample_1d(double u) const {
  const double r = filter_.radius;
  switch (filter_.kind) {
    case FilterKind::box:
      return (2 * u - 1) * r;
    case FilterKind::tent:
      // Inverse of the tent's cumulative distribution, (1 + x/r)^2 / 2 on [-r, 0].
      return u < 0.5 ? r * (std::sqrt(2 * u) - 1) : r * (1 - std::sqrt(2 - 2 * u));
    case FilterKind::gaussian:
      return sample_table(u);
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

}  // namespace tessera
