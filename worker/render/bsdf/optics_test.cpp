// Fresnel, reflection and refraction, and a chi-square test of cosine-hemisphere sampling.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "render/bsdf/fresnel.h"
#include "render/light/light_test_support.h"
#include "render/math/frame.h"
#include "render/sampling/warp.h"

namespace tessera {
namespace {

TEST(Fresnel, NormalIncidenceIsTheSquaredIndexRatio) {
  for (float n : {1.0f, 1.0001f, 1.33f, 1.5f, 2.5f, 3.0f, 10.0f}) {
    float cos_t;
    const float expected = ((n - 1) / (n + 1)) * ((n - 1) / (n + 1));
    EXPECT_NEAR(fresnel_dielectric(1.0f, n, &cos_t), expected, 1e-6f) << "n " << n;
    EXPECT_NEAR(cos_t, 1.0f, 1e-6f);
    // Leaving the medium at normal incidence reflects the same fraction.
    EXPECT_NEAR(fresnel_dielectric(1.0f, 1.0f / n, &cos_t), expected, 1e-6f);
  }
}

TEST(Fresnel, IndexOneIsInvisible) {
  for (float c = 0.01f; c <= 1.0f; c += 0.07f) {
    float cos_t;
    EXPECT_NEAR(fresnel_dielectric(c, 1.0f, &cos_t), 0.0f, 1e-6f);
    EXPECT_NEAR(cos_t, c, 1e-6f);
  }
}

TEST(Fresnel, TotalInternalReflectionPastTheCriticalAngle) {
  const float n = 1.5f;
  const float critical = std::asin(1.0f / n);
  float cos_t;
  EXPECT_EQ(fresnel_dielectric(std::cos(critical + 0.01f), 1.0f / n, &cos_t), 1.0f);
  EXPECT_EQ(cos_t, 0.0f);
  EXPECT_EQ(fresnel_dielectric(0.0f, 1.0f / n, &cos_t), 1.0f);
  EXPECT_LT(fresnel_dielectric(std::cos(critical - 0.01f), 1.0f / n, &cos_t), 1.0f);
}

TEST(Fresnel, GrazingIncidenceReflectsEverything) {
  float cos_t;
  EXPECT_NEAR(fresnel_dielectric(0.0f, 1.5f, &cos_t), 1.0f, 1e-6f);
  EXPECT_NEAR(fresnel_dielectric(1e-7f, 3.0f, &cos_t), 1.0f, 1e-5f);
}

TEST(Optics, ReflectionMirrorsAboutTheNormal) {
  const glm::vec3 n(0, 0, 1);
  const glm::vec3 wo = glm::normalize(glm::vec3(0.3f, -0.4f, 0.8f));
  const glm::vec3 wi = reflect(wo, n);
  EXPECT_NEAR(wi.x, -wo.x, 1e-6f);
  EXPECT_NEAR(wi.y, -wo.y, 1e-6f);
  EXPECT_NEAR(wi.z, wo.z, 1e-6f);
}

TEST(Optics, RefractionObeysSnellsLaw) {
  const glm::vec3 n(0, 0, 1);
  for (float eta : {1.0f, 1.0001f, 1.33f, 1.5f, 3.0f, 1.0f / 1.5f}) {
    for (float theta = 0.0f; theta < 1.5f; theta += 0.1f) {
      const glm::vec3 wo(std::sin(theta), 0.0f, std::cos(theta));
      float cos_t;
      if (fresnel_dielectric(wo.z, eta, &cos_t) == 1.0f) continue;  // TIR
      const glm::vec3 wt = refract(wo, n, eta, cos_t);
      EXPECT_NEAR(glm::length(wt), 1.0f, 1e-5f);
      EXPECT_LT(wt.z, 0.0f) << "transmitted to the other side";
      const float sin_t = std::sqrt(wt.x * wt.x + wt.y * wt.y);
      EXPECT_NEAR(std::sin(theta), eta * sin_t, 2e-5f) << "eta " << eta << " theta " << theta;
      EXPECT_LE(wt.x * wo.x, 0.0f) << "continues across the normal";
    }
  }
}

TEST(Frame, IsOrthonormalForAnyNormal) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int i = 0; i < 1000; ++i) {
    const glm::vec3 n = square_to_uniform_sphere({u(rng), u(rng)});
    const Frame f(n);
    EXPECT_NEAR(glm::dot(f.s, f.t), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(f.s, f.n), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(f.t, f.n), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::length(f.s), 1.0f, 1e-5f);
    EXPECT_NEAR(glm::length(f.t), 1.0f, 1e-5f);
  }
}

using test::chi_square_p_value;

TEST(CosineHemisphere, PassesAChiSquareTest) {
  constexpr int kThetaBins = 10, kPhiBins = 20, kSamples = 200000;
  std::vector<double> observed(kThetaBins * kPhiBins, 0.0);
  std::mt19937 rng(1234);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int i = 0; i < kSamples; ++i) {
    const glm::vec3 w = square_to_cosine_hemisphere({u(rng), u(rng)});
    ASSERT_GE(w.z, 0.0f);
    ASSERT_NEAR(glm::length(w), 1.0f, 1e-5f);
    const double theta = std::acos(std::min(1.0f, w.z));
    double phi = std::atan2(w.y, w.x);
    if (phi < 0) phi += 2 * M_PI;
    const int tb = std::min(kThetaBins - 1, int(theta / (M_PI / 2) * kThetaBins));
    const int pb = std::min(kPhiBins - 1, int(phi / (2 * M_PI) * kPhiBins));
    observed[size_t(tb * kPhiBins + pb)] += 1;
  }
  // Expected mass of a bin: integral of cos(theta)/pi sin(theta) dtheta dphi.
  double chi2 = 0;
  for (int tb = 0; tb < kThetaBins; ++tb) {
    const double t0 = tb * (M_PI / 2) / kThetaBins, t1 = (tb + 1) * (M_PI / 2) / kThetaBins;
    const double mass = (std::sin(t1) * std::sin(t1) - std::sin(t0) * std::sin(t0)) / 2.0 *
                        (2 * M_PI / kPhiBins) / M_PI;
    for (int pb = 0; pb < kPhiBins; ++pb) {
      const double expected = mass * kSamples;
      const double d = observed[size_t(tb * kPhiBins + pb)] - expected;
      chi2 += d * d / expected;
    }
  }
  const double p = chi_square_p_value(chi2, kThetaBins * kPhiBins - 1);
  EXPECT_GT(p, 1e-3) << "chi2 " << chi2;
}

TEST(SinCosQuarterPi, WithinOneUlpOfTheExactValues) {
  // Every 997th float of [0, pi/4] (about a million, subnormals to pi/4), both signs:
  // square_to_concentric_disk's angles; the polynomials must stay within 1 ulp (measured on
  // every 64th float: 0.73 for sin, 0.97 for cos).
  const float limit = kPi / 4.0f;
  uint32_t limit_bits;
  std::memcpy(&limit_bits, &limit, sizeof limit_bits);
  double worst_sin = 0, worst_cos = 0;
  for (uint32_t bits = 1; bits <= limit_bits; bits += 997) {
    for (const uint32_t sign : {0u, 0x80000000u}) {
      const uint32_t signed_bits = bits | sign;
      float x;
      std::memcpy(&x, &signed_bits, sizeof x);
      float s, c;
      sincos_quarter_pi(x, &s, &c);
      const float exact_s = float(std::sin(double(x))), exact_c = float(std::cos(double(x)));
      const double ulp_s = std::nextafter(std::abs(exact_s), 1.0f) - std::abs(exact_s);
      const double ulp_c = std::nextafter(exact_c, 2.0f) - exact_c;
      worst_sin = std::max(worst_sin, std::abs(double(s) - std::sin(double(x))) / ulp_s);
      worst_cos = std::max(worst_cos, std::abs(double(c) - std::cos(double(x))) / ulp_c);
    }
  }
  EXPECT_LE(worst_sin, 1.0);
  EXPECT_LE(worst_cos, 1.0);
}

TEST(ConcentricDisk, MatchesTheExactMapInEverySector) {
  // The map with libm's sin and cos in double, on a grid of the square: the same points to
  // within a few float ulps, in all eight sectors (both branches, both signs).
  for (int i = 0; i < 64; ++i) {
    for (int j = 0; j < 64; ++j) {
      const glm::vec2 u((float(i) + 0.37f) / 64.0f, (float(j) + 0.61f) / 64.0f);
      const double ox = 2.0 * u.x - 1.0, oy = 2.0 * u.y - 1.0;
      double r, theta;
      if (std::abs(ox) > std::abs(oy)) {
        r = ox;
        theta = (M_PI / 4) * (oy / ox);
      } else {
        r = oy;
        theta = M_PI / 2 - (M_PI / 4) * (ox / oy);
      }
      const glm::vec2 d = square_to_concentric_disk(u);
      EXPECT_NEAR(d.x, r * std::cos(theta), 4e-7) << u.x << " " << u.y;
      EXPECT_NEAR(d.y, r * std::sin(theta), 4e-7) << u.x << " " << u.y;
    }
  }
}

TEST(CosineHemisphere, PdfIntegratesToOne) {
  // Midpoint rule over theta: integral of cos/pi * sin * 2pi dtheta = 1.
  double sum = 0;
  const int n = 100000;
  for (int i = 0; i < n; ++i) {
    const double theta = (i + 0.5) * (M_PI / 2) / n;
    sum += cosine_hemisphere_pdf(float(std::cos(theta))) * std::sin(theta) * 2 * M_PI * (M_PI / 2) / n;
  }
  EXPECT_NEAR(sum, 1.0, 1e-4);
}

TEST(Triangle, UniformMapCoversTheTriangleEvenly) {
  // Quadrant test: the four sub-triangles of the midpoint subdivision get a quarter each.
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  int counts[4] = {0, 0, 0, 0};
  const int n = 100000;
  for (int i = 0; i < n; ++i) {
    const glm::vec2 b = square_to_triangle({u(rng), u(rng)});
    ASSERT_GE(b.x, 0.0f);
    ASSERT_GE(b.y, 0.0f);
    ASSERT_LE(b.x + b.y, 1.0f);
    const int q = b.x > 0.5f ? 1 : b.y > 0.5f ? 2 : (b.x + b.y < 0.5f ? 0 : 3);
    ++counts[q];
  }
  for (int c : counts) EXPECT_NEAR(double(c) / n, 0.25, 0.01);
}

}  // namespace
}  // namespace tessera
