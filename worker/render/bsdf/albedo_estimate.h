// Test support: a BSDF's directional albedo estimated from its sample(), as the tests compare it
// with the tables Mitsuba 3 made (mitsuba_points.py's albedo: wo at azimuth 30 degrees).
#pragma once

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include <glm/common.hpp>
#include <glm/exponential.hpp>
#include <gtest/gtest.h>

#include "render/bsdf/bsdf.h"
#include "render/bsdf/chi_square.h"

namespace tessera::test {

/// wo = (sin t cos 30deg, sin t sin 30deg, cos t): the direction of the reference tables, at
/// an azimuth where anisotropic rows depend on both alphas.
inline glm::vec3 albedo_wo(float cos_theta_o) {
  const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta_o * cos_theta_o));
  return {sin_theta * std::cos(kPi / 6), sin_theta * std::sin(kPi / 6), cos_theta_o};
}

/// The mean of sample()'s weight over a jittered 256 x 256 grid of direction samples (lobe
/// choice random) and its standard error (ignoring the stratification: an upper bound).
/// energy: times the sample's eta^2, undoing the 1 / eta^2 of a refraction.
struct AlbedoEstimate {
  glm::dvec3 mean{0.0}, se{0.0};
};
inline AlbedoEstimate grid_albedo(const Bsdf& bsdf, glm::vec3 wo, uint64_t seed, bool energy) {
  constexpr int kGrid = 256;
  std::mt19937_64 rng(seed);
  glm::dvec3 sum(0.0), sum2(0.0);
  for (int i = 0; i < kGrid; ++i) {
    for (int j = 0; j < kGrid; ++j) {
      const glm::vec2 u((i + u01(rng)) / kGrid, (j + u01(rng)) / kGrid);
      const auto s = bsdf.sample(wo, u01(rng), u);
      glm::dvec3 w(0.0);
      if (s) w = glm::dvec3(s->weight) * (energy ? double(s->eta) * s->eta : 1.0);
      sum += w;
      sum2 += w * w;
    }
  }
  const double n = double(kGrid) * kGrid;
  AlbedoEstimate e;
  e.mean = sum / n;
  e.se = glm::sqrt(glm::max(sum2 / n - e.mean * e.mean, 0.0) / n);
  return e;
}

/// Expects `ours` within 1 % of Mitsuba's `expected` (standard errors expected_se), widened to
/// 4 standard errors of both estimates where the noise is larger; returns the largest relative
/// difference of the three channels.
inline double expect_albedo_near(const AlbedoEstimate& ours, glm::dvec3 expected,
                                 glm::dvec3 expected_se, const std::string& where) {
  double worst = 0;
  for (int c = 0; c < 3; ++c) {
    worst = std::max(worst, std::abs(ours.mean[c] - expected[c]) / std::max(expected[c], 1e-2));
    const double allowed =
        std::max(0.01 * expected[c], 4 * (ours.se[c] + expected_se[c])) + 1e-4;
    EXPECT_NEAR(ours.mean[c], expected[c], allowed)
        << where << " channel " << c << ": ours +- " << ours.se[c] << ", Mitsuba's +- "
        << expected_se[c];
  }
  return worst;
}

}  // namespace tessera::test
