#include "pixel_filter.h"

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "renderer.h"
#include "sampler.h"
#include "test_scenes.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

PixelFilter box() { return {FilterKind::box, 0.5, 0.5}; }
PixelFilter tent() { return {FilterKind::tent, 1.0, 0.5}; }
PixelFilter gaussian(double stddev = 0.5) { return {FilterKind::gaussian, 4 * stddev, stddev}; }

/// The filter's profile from its definition with libm's exp (independent of the sampler's own
/// arithmetic).
double reference_profile(const PixelFilter& f, double x) {
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
  }
  return 0;
}

/// Integral of x^k f(x) over [lo, hi] by Simpson's rule on n (even) intervals.
double integrate(const PixelFilter& f, double lo, double hi, int k, int n = 20000) {
  const double h = (hi - lo) / n;
  double sum = 0;
  for (int i = 0; i <= n; ++i) {
    const double x = lo + h * i;
    const double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
    sum += w * std::pow(x, k) * reference_profile(f, x);
  }
  return sum * h / 3;
}

/// Uniform doubles in [0, 1) from a fixed-seed generator, by an explicit bit recipe (the
/// standard distributions are implementation-defined).
struct Uniform {
  std::mt19937_64 rng;
  explicit Uniform(uint64_t seed) : rng(seed) {}
  double operator()() { return double(rng() >> 11) * 0x1.0p-53; }
};

TEST(PixelFilter, ProfilesFollowMitsubasDefinitions) {
  for (const PixelFilter& f : {box(), tent(), gaussian(), gaussian(0.3)}) {
    for (double x = -2.5; x <= 2.5; x += 0.01) {
      EXPECT_NEAR(PixelFilterSampler::profile(f, x), reference_profile(f, x), 1e-12) << x;
    }
  }
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
  for (const PixelFilter& f : {box(), tent(), gaussian(), PixelFilter{FilterKind::box, 1.5, 0.5}}) {
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

/// Chi-square of the histogram of sampled offsets (2D, both components) against the filter.
/// Bins whose expected count is under 5 are pooled. The threshold is the chi-square quantile
/// for p = 1e-6 (Wilson-Hilferty), so a correct sampler fails with probability 1e-6 per seed
/// and the fixed seed makes the outcome reproducible.
void expect_histogram_matches(const PixelFilter& f) {
  const PixelFilterSampler sampler(f);
  const int bins = 40, n = 200000;
  const double r = f.radius, total = integrate(f, -r, r, 0);
  std::vector<double> observed(size_t(bins * bins), 0), expected(size_t(bins * bins), 0);
  std::vector<double> p1(static_cast<size_t>(bins));
  for (int b = 0; b < bins; ++b) {
    p1[size_t(b)] =
        integrate(f, -r + 2 * r * b / bins, -r + 2 * r * (b + 1) / bins, 0, 2000) / total;
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

/// The density of the sampled offsets, 1 / (dx/du) by central differences of the inverse CDF,
/// against the normalised filter: the gaussian's table must match it to 1e-4 of the peak.
void expect_density_matches(const PixelFilter& f, double tolerance) {
  const PixelFilterSampler sampler(f);
  const double total = integrate(f, -f.radius, f.radius, 0), peak = reference_profile(f, 0) / total;
  const double h = 1e-5;
  double worst = 0;
  for (double u = 0.001; u < 0.999; u += 0.0007) {
    const double x = sampler.sample_1d(u);
    const double sampled = 2 * h / (sampler.sample_1d(u + h) - sampler.sample_1d(u - h));
    const double exact = reference_profile(f, x) / total;
    worst = std::max(worst, std::abs(sampled - exact) / peak);
  }
  EXPECT_LT(worst, tolerance);
}

TEST(PixelFilter, SampledDensityEqualsTheFilter) {
  expect_density_matches(tent(), 1e-4);
  expect_density_matches(gaussian(), 1e-4);
  expect_density_matches(gaussian(0.3), 1e-4);
  expect_density_matches(gaussian(1.0), 1e-4);
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

/// The renderer draws film positions from Scene::film.filter: an emitter covering exactly the
/// left half of an 8x1 image (its edge between pixels 3 and 4, radiance 1, nothing else in the
/// scene) lights pixel 4 by the filter's weight beyond half a pixel to its left. 256 samples of
/// a (0, 2)-sequence put the sampled fraction within 1/256 of the filter's.
TEST(PixelFilter, TheRendererSamplesTheScenesFilter) {
  Scene s;
  s.camera.position = {0, 0, 1};
  s.camera.look_at = {0, 0, 0};
  s.camera.up = {0, 1, 0};
  s.camera.fov_deg = 90;  // along x: film x in [0, 8) spans X in [-1, 1] on the plane z = 0
  const uint32_t black = test::add_diffuse(s, {0, 0, 0});
  Shape light = test::quad({-10, -10, 0}, {0, -10, 0}, {0, 10, 0}, {-10, 10, 0}, black);
  light.emission = {1, 1, 1};
  s.shapes.push_back(light);
  JobOptions job;
  job.width = 8;
  job.height = 1;
  job.spp = 256;
  job.batch_spp = 256;
  job.seed = 5;
  const auto render = [&](const PixelFilter& f) {
    s.film.filter = f;
    const Accumulation acc = Renderer(s, job).render({0, 0, 8, 1}, 0, 256);
    std::vector<double> pixels;
    for (size_t i = 0; i < 8; ++i) pixels.push_back(acc.rgb[i * 3 + 1] / acc.count[i]);
    return pixels;
  };
  const std::vector<double> b = render(box());
  // Which side is lit depends on the camera's handedness; the box tells.
  const bool left_lit = b[0] > 0.5;
  const auto pixel = [&](const std::vector<double>& p, int k) {
    return left_lit ? p[size_t(4 + k)] : p[size_t(3 - k)];
  };
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(pixel(b, k), 0.0) << k;
    EXPECT_EQ(pixel(b, -1 - k), 1.0) << k;
  }
  const std::vector<double> t = render(tent());
  EXPECT_NEAR(pixel(t, 0), 0.125, 1.0 / 256);  // the tent's weight beyond -1/2
  EXPECT_NEAR(pixel(t, -1), 0.875, 1.0 / 256);
  EXPECT_EQ(pixel(t, 1), 0.0);
  const PixelFilter g = gaussian();
  const std::vector<double> gp = render(g);
  const double total = integrate(g, -2, 2, 0);
  EXPECT_NEAR(pixel(gp, 0), integrate(g, -2, -0.5, 0) / total, 1.0 / 256);
  EXPECT_NEAR(pixel(gp, 1), integrate(g, -2, -1.5, 0) / total, 1.0 / 256);
  EXPECT_NEAR(pixel(gp, -1), integrate(g, -2, 0.5, 0) / total, 1.0 / 256);
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
}

}  // namespace
}  // namespace tessera
