#include "render/camera/pixel_filter.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "render/camera/pixel_filter_test_support.h"
#include "render/sampling/sampler.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

using namespace pixel_filter_test;

/// Uniform doubles in [0, 1) from a fixed-seed generator, by an explicit bit recipe (the
/// standard distributions are implementation-defined).
struct Uniform {
  std::mt19937_64 rng;
  explicit Uniform(uint64_t seed) : rng(seed) {}
  double operator()() { return double(rng() >> 11) * 0x1.0p-53; }
};

TEST(PixelFilter, ProfilesFollowMitsubasDefinitions) {
  for (const PixelFilter& f : {box(), tent(), gaussian(), gaussian(0.3), mitchell(), catmullrom(), mitchell(1, 0),
                               lanczos(), lanczos(2), lanczos(9)}) {
    for (double x = -9.5; x <= 9.5; x += 0.01) {
      EXPECT_NEAR(PixelFilterSampler::profile(f, x), reference_profile(f, x), 1e-12) << x << " kind " << int(f.kind);
    }
  }
  // Mitsuba's values: the mitchell's peak (6 - 2B) / 6 and its negative lobe, the lanczos zeros.
  EXPECT_NEAR(PixelFilterSampler::profile(mitchell(), 0), 8.0 / 9, 1e-15);
  EXPECT_LT(PixelFilterSampler::profile(mitchell(), 1.5), 0);
  EXPECT_NEAR(PixelFilterSampler::profile(lanczos(), 1.0), 0, 1e-16);
  EXPECT_LT(PixelFilterSampler::profile(lanczos(), 1.5), 0);
  EXPECT_GT(PixelFilterSampler::profile(lanczos(), 2.5), 0);
  EXPECT_EQ(PixelFilterSampler::profile(lanczos(), 3.0001), 0.0);
  EXPECT_EQ(PixelFilterSampler::profile(gaussian(), 2.0), 0.0);
  EXPECT_EQ(PixelFilterSampler::profile(tent(), 1.0), 0.0);
  EXPECT_EQ(PixelFilterSampler::profile(tent(), 0.25), 0.75);
}

TEST(PixelFilter, BoxKeepsTheFilmPositionOfBeforeBitForBit) {
  const PixelFilterSampler sampler(box());
  for (uint32_t i = 0; i < 20000; ++i) {
    const int x = int(i % 997), y = int(i / 997) * 31;
    PixelSampler s(12345, x, y, i);
    const glm::vec2 u = s.get2d();
    const glm::vec2 p = sampler.film_position(x, y, u);
    // The expression renderer.cpp used before pixel filters existed.
    const glm::vec2 before{float(x) + u.x, float(y) + u.y};
    ASSERT_EQ(p.x, before.x) << i;
    ASSERT_EQ(p.y, before.y) << i;
  }
}

TEST(PixelFilter, OffsetsStayInsideTheFootprintAndAreMonotonic) {
  for (const PixelFilter& f :
       {box(), tent(), gaussian(), PixelFilter{FilterKind::box, 1.5, 0.5}, mitchell(), lanczos()}) {
    const PixelFilterSampler sampler(f);
    double previous = -f.radius;
    for (int k = 0; k <= 100000; ++k) {
      const double u = k == 100000 ? std::nextafter(1.0, 0.0) : k / 100000.0;
      const double x = sampler.sample_1d(u);
      ASSERT_GE(x, -f.radius) << u;
      ASSERT_LE(x, f.radius) << u;
      ASSERT_GE(x, previous) << u;
      previous = x;
    }
    const glm::vec2 p = sampler.film_position(7, 3, {0.999999f, 0.0f});
    EXPECT_LE(p.x, 7.5f + float(f.radius));
    EXPECT_GE(p.y, 3.5f - float(f.radius));
  }
}

/// Chi-square of the histogram of sampled offsets (2D, both components) against the filter
/// (its magnitude: filters with negative lobes are sampled by |f|).
/// Bins whose expected count is under 5 are pooled. The threshold is the chi-square quantile
/// for p = 1e-6 (Wilson-Hilferty), so a correct sampler fails with probability 1e-6 per seed
/// and the fixed seed makes the outcome reproducible.
void expect_histogram_matches(const PixelFilter& f) {
  const PixelFilterSampler sampler(f);
  const int bins = 40, n = 200000;
  const double r = f.radius, total = integrate(f, -r, r, 0, 20000, true);
  std::vector<double> observed(size_t(bins * bins), 0), expected(size_t(bins * bins), 0);
  std::vector<double> p1(static_cast<size_t>(bins));
  for (int b = 0; b < bins; ++b) {
    p1[size_t(b)] =
        integrate(f, -r + 2 * r * b / bins, -r + 2 * r * (b + 1) / bins, 0, 2000, true) / total;
  }
  for (int by = 0; by < bins; ++by)
    for (int bx = 0; bx < bins; ++bx)
      expected[size_t(by * bins + bx)] = n * p1[size_t(bx)] * p1[size_t(by)];
  Uniform uniform(0x5eed + uint64_t(f.kind));
  for (int i = 0; i < n; ++i) {
    const glm::vec2 d = sampler.sample({float(uniform()), float(uniform())});
    const int bx = std::clamp(int((d.x + r) / (2 * r) * bins), 0, bins - 1);
    const int by = std::clamp(int((d.y + r) / (2 * r) * bins), 0, bins - 1);
    observed[size_t(by * bins + bx)] += 1;
  }
  double chi2 = 0, pooled_obs = 0, pooled_exp = 0;
  int dof = -1;
  for (size_t i = 0; i < observed.size(); ++i) {
    if (expected[i] < 5) {
      pooled_obs += observed[i];
      pooled_exp += expected[i];
      continue;
    }
    chi2 += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
    ++dof;
  }
  if (pooled_exp > 0) {
    chi2 += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
    ++dof;
  }
  const double z = 4.753;  // standard normal quantile of 1 - 1e-6
  const double k = dof, threshold = k * std::pow(1 - 2 / (9 * k) + z * std::sqrt(2 / (9 * k)), 3);
  EXPECT_LT(chi2, threshold) << "dof " << dof;
}

TEST(PixelFilter, BoxHistogramMatchesTheFilter) { expect_histogram_matches(box()); }
TEST(PixelFilter, TentHistogramMatchesTheFilter) { expect_histogram_matches(tent()); }
TEST(PixelFilter, GaussianHistogramMatchesTheFilter) { expect_histogram_matches(gaussian()); }
TEST(PixelFilter, MitchellHistogramMatchesTheFilter) { expect_histogram_matches(mitchell()); }
TEST(PixelFilter, LanczosHistogramMatchesTheFilter) { expect_histogram_matches(lanczos()); }

/// The filter the samples apply: the density of the sampled offsets, 1 / (dx/du) by central
/// differences of the inverse CDF, times the sample's weight, against the normalised filter
/// f / integral f: the tables must match it to 1e-4 of the peak. (Where a filter changes sign
/// the density alone, linear between the table's nodes, departs from |f|'s kink by up to
/// |f'| dx / 4; the weight undoes that.)
void expect_density_matches(const PixelFilter& f, double tolerance) {
  const PixelFilterSampler sampler(f);
  const double total = integrate(f, -f.radius, f.radius, 0), peak = reference_profile(f, 0) / total;
  // A small step in u: near a sign change the density is small, and a wide difference would
  // average it over a stretch of x where it varies by a large factor.
  const double h = 1e-8;
  double worst = 0;
  for (double u = 0.001; u < 0.999; u += 0.0007) {
    double w = 0;
    const double x = sampler.sample_1d(u, &w);
    const double sampled = w * 2 * h / (sampler.sample_1d(u + h) - sampler.sample_1d(u - h));
    const double exact = reference_profile(f, x) / total;
    worst = std::max(worst, std::abs(sampled - exact) / peak);
  }
  EXPECT_LT(worst, tolerance) << "kind " << int(f.kind) << " radius " << f.radius << " b " << f.b;
}

TEST(PixelFilter, SampledDensityEqualsTheFilter) {
  expect_density_matches(tent(), 1e-4);
  expect_density_matches(gaussian(), 1e-4);
  expect_density_matches(gaussian(0.3), 1e-4);
  expect_density_matches(gaussian(1.0), 1e-4);
  expect_density_matches(mitchell(), 1e-4);
  expect_density_matches(catmullrom(), 1e-4);
  expect_density_matches(lanczos(2), 1e-4);
  expect_density_matches(lanczos(), 1e-4);
  expect_density_matches(lanczos(4), 1e-4);
  expect_density_matches(lanczos(9), 1e-4);
}

/// Filters with negative lobes: a sample's weight w makes w g(X) an unbiased estimate of the
/// normalised filter's integral of g, integral f g / integral f, for any g. Checked by the
/// midpoint rule over u (deterministic) for g = 1, x^2, the step x < -1/2 (the light beyond a
/// pixel's edge: pixel 4 of TheRendererSamplesTheScenesFilter, pixel_filter_render_test.cpp) and x > 1 (in a negative lobe).
/// Filters that are never negative give weight 1 everywhere.
TEST(PixelFilter, WeightsMakeTheSignedFilterUnbiased) {
  for (const PixelFilter& f : {mitchell(), catmullrom(), mitchell(1, 0), lanczos(2), lanczos(), lanczos(5)}) {
    const PixelFilterSampler sampler(f);
    ASSERT_EQ(sampler.signed_weights(), f.kind == FilterKind::lanczos || f.b < 1) << int(f.kind);
    const double r = f.radius, total = integrate(f, -r, r, 0);
    const int m = 400000;
    double sum1 = 0, sum2 = 0, step = 0, lobe = 0, largest = 0;
    for (int k = 0; k < m; ++k) {
      double w = 0;
      const double x = sampler.sample_1d((k + 0.5) / m, &w);
      ASSERT_TRUE(std::isfinite(w));
      ASSERT_TRUE(w == 0 || (w < 0) == (reference_profile(f, x) < 0) || std::abs(reference_profile(f, x)) < 1e-3)
          << x << " " << w;
      sum1 += w;
      sum2 += w * x * x;
      if (x < -0.5) step += w;
      if (x > 1) lobe += w;
      largest = std::max(largest, std::abs(w));
    }
    const double abs_total = integrate(f, -r, r, 0, 20000, true);
    EXPECT_NEAR(sum1 / m, 1.0, 1e-5) << int(f.kind) << " r " << r;
    EXPECT_NEAR(sum2 / m, integrate(f, -r, r, 2) / total, 1e-4) << int(f.kind) << " r " << r;
    EXPECT_NEAR(step / m, integrate(f, -r, -0.5, 0) / total, 1e-4) << int(f.kind) << " r " << r;
    EXPECT_NEAR(lobe / m, integrate(f, 1, r, 0) / total, 1e-4) << int(f.kind) << " r " << r;
    EXPECT_NEAR(largest, abs_total / total, 1e-5 * abs_total / total) << int(f.kind);
  }
  // B = 1, C = 0 is the cubic B-spline: never negative, so weight 1 and no signed samples.
  for (const PixelFilter& f : {box(), tent(), gaussian(), mitchell(1, 0)}) {
    const PixelFilterSampler sampler(f);
    EXPECT_FALSE(sampler.signed_weights());
    for (double u : {0.1, 0.5, 0.93}) {
      double w = -7;
      sampler.sample_1d(u, &w);
      EXPECT_EQ(w, 1.0);
      EXPECT_EQ(sampler.film_sample(3, 4, {float(u), 0.25f}).weight, 1.0);
    }
  }
}

/// Mean and variance of the offsets by the midpoint rule over u (deterministic, no noise):
/// E[g(X)] = integral over u of g(sample(u)).
TEST(PixelFilter, OffsetMeanIsZeroAndVarianceIsTheFilters) {
  for (const PixelFilter& f : {box(), tent(), gaussian(), gaussian(0.3)}) {
    const PixelFilterSampler sampler(f);
    const int m = 200000;
    double mean = 0, second = 0;
    for (int k = 0; k < m; ++k) {
      const double x = sampler.sample_1d((k + 0.5) / m);
      mean += x;
      second += x * x;
    }
    mean /= m;
    second /= m;
    const double r = f.radius;
    const double variance = integrate(f, -r, r, 2) / integrate(f, -r, r, 0);
    EXPECT_NEAR(mean, 0, 1e-9) << int(f.kind);
    EXPECT_NEAR(second, variance, 1e-5 * variance) << int(f.kind);
  }
  EXPECT_NEAR(integrate(tent(), -1, 1, 2) / integrate(tent(), -1, 1, 0), 1.0 / 6, 1e-9);
  EXPECT_NEAR(integrate(box(), -0.5, 0.5, 2), 1.0 / 12, 1e-9);
}

TEST(PixelFilter, RefusesABadRadiusOrStddevNamingTheKey) {
  try {
    PixelFilterSampler s(PixelFilter{FilterKind::tent, 0.0, 0.5});
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("film.filter.radius"), std::string::npos) << e.what();
  }
  try {
    PixelFilterSampler s(PixelFilter{FilterKind::gaussian, 2.0, std::nan("")});
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("film.filter.stddev"), std::string::npos) << e.what();
  }
  try {
    PixelFilterSampler s(mitchell(std::numeric_limits<double>::infinity()));
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("film.filter.b"), std::string::npos) << e.what();
  }
  // Finite but extreme: the cubic's coefficients overflow, so the filter has no finite integral.
  try {
    PixelFilterSampler s(mitchell(1e308, 1e308));
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("film.filter"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tessera
