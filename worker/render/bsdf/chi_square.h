// Test support: Pearson's chi-square test of a BSDF's sample() against its pdf() (pbrt-v4's and
// Mitsuba's BSDF tests): the sphere of directions wi is cut into theta x phi bins, each bin's
// expected count is the numerically integrated pdf, and the observed counts come from sample().
// Deterministic: the random numbers come from a fixed seed.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "render/bsdf/bsdf.h"
#include "render/sampling/warp.h"

namespace tessera::test {

/// Uniform float in [0, 1) from 24 random bits (same numbers on every platform, unlike
/// std::uniform_real_distribution).
inline float u01(std::mt19937_64& rng) { return float(rng() >> 40) * 0x1p-24f; }

/// The unit direction with polar angle theta (from +z) and azimuth phi.
inline glm::vec3 spherical(float theta, float phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

/// Regularized upper incomplete gamma Q(a, x) (series and Lentz's continued fraction).
inline double gamma_q(double a, double x) {
  if (x <= 0) return 1;
  const double log_prefix = -x + a * std::log(x) - std::lgamma(a);
  if (x < a + 1) {
    double sum = 1 / a, term = sum;
    for (int n = 1; n < 100000 && std::abs(term) > std::abs(sum) * 1e-15; ++n) {
      term *= x / (a + n);
      sum += term;
    }
    return 1 - sum * std::exp(log_prefix);
  }
  double b = x + 1 - a, c = 1e300, d = 1 / b, h = d;
  for (int i = 1; i < 100000; ++i) {
    const double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    if (std::abs(d) < 1e-300) d = 1e-300;
    c = b + an / c;
    if (std::abs(c) < 1e-300) c = 1e-300;
    d = 1 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1) < 1e-15) break;
  }
  return std::exp(log_prefix) * h;
}

struct ChiSquareResult {
  bool passed = false;
  double p_value = 0;
  int dof = 0;
  std::string message;  ///< why it failed, for the test log
};

/// Pearson's test of counts `observed` against `expected` (the same bins), rejecting at
/// significance `alpha`: the bins expecting fewer than 5 samples pooled into one, as the
/// approximation needs; failed with a message when the pool holds far more samples than it
/// expects (samples where the density is ~0) or fewer than two bins are left.
inline ChiSquareResult pearson_test(const std::vector<double>& observed, const std::vector<double>& expected,
                                    double alpha) {
  ChiSquareResult r;
  double chi2 = 0, pooled_obs = 0, pooled_exp = 0;
  int bins = 0;
  for (size_t i = 0; i < observed.size(); ++i) {
    if (expected[i] < 5) {
      pooled_obs += observed[i];
      pooled_exp += expected[i];
    } else {
      chi2 += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
      ++bins;
    }
  }
  if (pooled_exp >= 5) {
    chi2 += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
    ++bins;
  } else if (pooled_obs > 20 + 5 * pooled_exp) {
    r.message = "samples where pdf() is ~0: " + std::to_string(pooled_obs) + " observed, " +
                std::to_string(pooled_exp) + " expected";
    return r;
  }
  if (bins < 2) {
    r.message = "fewer than two bins with enough samples";
    return r;
  }
  r.dof = bins - 1;
  r.p_value = gamma_q(r.dof / 2.0, chi2 / 2.0);
  r.passed = r.p_value >= alpha;
  if (!r.passed) {
    r.message = "chi2 " + std::to_string(chi2) + " dof " + std::to_string(r.dof) + " p " +
                std::to_string(r.p_value);
  }
  return r;
}

/// Runs the test for `bsdf` and wo with `samples` samples (delta samples are left out: pdf()
/// covers the smooth lobes only, with the probability of choosing them included), rejecting at
/// significance `alpha` (already corrected for the number of tests run). `B` is Bsdf or any
/// BSDF class of worker/render/bsdf/ (sample() and pdf() with Bsdf's signatures).
template <typename B>
ChiSquareResult chi_square_test(const B& bsdf, glm::vec3 wo, uint64_t seed, int samples,
                                double alpha) {
  constexpr int kTheta = 16, kPhi = 32, kSub = 16;  // bins; integration cells per bin side
  const float dtheta = kPi / kTheta, dphi = 2 * kPi / kPhi;
  std::vector<double> observed(kTheta * kPhi, 0), expected(kTheta * kPhi, 0);
  std::mt19937_64 rng(seed);
  for (int i = 0; i < samples; ++i) {
    const float u_lobe = u01(rng);
    const glm::vec2 u(u01(rng), u01(rng));
    const auto s = bsdf.sample(wo, u_lobe, u);
    if (!s || s->delta) continue;
    const float theta = std::acos(std::clamp(s->wi.z, -1.0f, 1.0f));
    float phi = std::atan2(s->wi.y, s->wi.x);
    if (phi < 0) phi += 2 * kPi;
    const int ti = std::min(kTheta - 1, int(theta / dtheta));
    const int pi = std::min(kPhi - 1, int(phi / dphi));
    observed[ti * kPhi + pi] += 1;
  }
  // The midpoint rule over kSub x kSub cells per bin of sin(theta) pdf(theta, phi): robust to
  // the kinks and jumps of the pdfs (total internal reflection, the horizon), where Simpson's
  // rule is not.
  for (int ti = 0; ti < kTheta; ++ti) {
    for (int pi = 0; pi < kPhi; ++pi) {
      const double h_t = dtheta / kSub, h_p = dphi / kSub;
      double sum = 0;
      for (int a = 0; a < kSub; ++a) {
        const float theta = float(ti * dtheta + (a + 0.5) * h_t);
        for (int b = 0; b < kSub; ++b) {
          const float phi = float(pi * dphi + (b + 0.5) * h_p);
          sum += bsdf.pdf(wo, spherical(theta, phi)) * std::sin(theta);
        }
      }
      expected[ti * kPhi + pi] = sum * h_t * h_p * samples;
    }
  }
  return pearson_test(observed, expected, alpha);
}

}  // namespace tessera::test
