// Properties every BSDF must have: white furnace (energy conservation, exactly 1 when
// lossless), sample() consistent with eval() and pdf(), reciprocity, finite values at the
// extremes, and the Fresnel helpers against closed forms.
#include <cmath>
#include <cstring>
#include <random>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "render/bsdf/bsdf.h"
#include "render/bsdf/bsdf_test_cases.h"
#include "render/bsdf/fresnel.h"
#include "render/bsdf/material.h"
#include "render/bsdf/rough_plastic_tables.h"
#include "render/texture/texture_set.h"

namespace tessera::test {
namespace {


/// The energy a sample carries: its weight without the radiance compression 1 / eta^2 of a
/// refraction, so that a lossless interface conserves it exactly.
glm::vec3 energy(const BsdfSample& s) { return s.weight * (s.eta * s.eta); }

struct Mean {
  glm::dvec3 sum{0.0}, sum2{0.0};
  int n = 0;
  void add(glm::vec3 v) {
    sum += glm::dvec3(v);
    sum2 += glm::dvec3(v) * glm::dvec3(v);
    ++n;
  }
  double mean(int c) const { return sum[c] / n; }
  double se(int c) const { return std::sqrt(std::max(0.0, sum2[c] / n - mean(c) * mean(c)) / n); }
};

Mean furnace(const Bsdf& bsdf, glm::vec3 wo, uint64_t seed, int samples) {
  Mean m;
  std::mt19937_64 rng(seed);
  for (int i = 0; i < samples; ++i) {
    const float u_lobe = u01(rng);
    const glm::vec2 u(u01(rng), u01(rng));
    const auto s = bsdf.sample(wo, u_lobe, u);
    m.add(s ? energy(*s) : glm::vec3(0.0f));
  }
  return m;
}

TEST(BsdfFurnace, LosslessMaterialsReturnExactlyOne) {
  BsdfParams diffuse;
  diffuse.reflectance = glm::vec3(1.0f);
  BsdfParams mirror;
  mirror.type = MaterialType::mirror;
  BsdfParams perfect;
  perfect.type = MaterialType::conductor;
  perfect.perfect = true;
  perfect.conductor_eta = glm::vec3(1.3f);  // ignored when perfect
  BsdfParams none;  // Mitsuba's material="none" defaults: eta 0, k 1 is a perfect mirror too
  none.type = MaterialType::conductor;
  for (const BsdfParams& p : {diffuse, mirror, perfect, none}) {
    for (glm::vec3 wo : test_wos(false)) {
      const Mean m = furnace(Bsdf(p), wo, 3, 2000);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(m.mean(c), 1.0, 1e-5) << int(p.type);
    }
  }
}

TEST(BsdfFurnace, SmoothDielectricsSplitEnergyByFresnel) {
  for (MaterialType type : {MaterialType::glass, MaterialType::thin_glass}) {
    for (float eta : {1.5f, 1.0f / 1.5f, 1.0001f, 2.4f}) {
      BsdfParams p;
      p.type = type;
      p.eta = eta;
      const Bsdf bsdf(p);
      for (glm::vec3 wo : test_wos(true)) {
        std::mt19937_64 rng(7);
        Mean m;
        int reflected = 0;
        const int n = 20000;
        for (int i = 0; i < n; ++i) {
          const auto s = bsdf.sample(wo, u01(rng), {u01(rng), u01(rng)});
          ASSERT_TRUE(s);
          EXPECT_TRUE(s->delta);
          m.add(energy(*s));
          reflected += s->wi.z * wo.z > 0;
        }
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(m.mean(c), 1.0, 1e-5) << "R + T = 1";
        float r = fresnel_dielectric_signed(wo.z, eta).r;
        if (type == MaterialType::thin_glass) {
          r = fresnel_dielectric_signed(std::abs(wo.z), eta).r;
          r = 2 * r / (1 + r);
        }
        const double se = std::sqrt(std::max(r * (1 - r), 1e-12f) / n);
        EXPECT_NEAR(double(reflected) / n, r, 5 * se + 1e-6) << "eta " << eta << " wo.z " << wo.z;
      }
    }
  }
}

TEST(BsdfFurnace, NoBsdfCreatesEnergy) {
  const BsdfCases cases;
  uint64_t seed = 100;
  for (BsdfCase c : cases.all()) {
    // Mitsuba's principled adds retro-reflection, sheen and a clear coat on top of the rest and
    // so exceeds 1 at grazing angles: principled_test.cpp checks its albedo against Mitsuba's
    // and the furnace of its energy-conserving lobes.
    // principled_thin_test.cpp does the same for the thin one.
    if (c.params.type == MaterialType::principled ||
        c.params.type == MaterialType::principled_thin) {
      continue;
    }
    // White parameters make the bound tight: 1 is reached only by lossless materials.
    c.params.reflectance = c.params.specular_reflectance = glm::vec3(1.0f);
    c.params.specular_transmittance = glm::vec3(1.0f);
    for (BsdfParams& nested : c.params.blend) nested.reflectance = glm::vec3(1.0f);
    const Bsdf bsdf(c.params);  // a rough plastic's table does not depend on the colours
    for (glm::vec3 wo : test_wos(c.two_sided_wo)) {
      const Mean m = furnace(bsdf, wo, seed++, 20000);
      for (int ch = 0; ch < 3; ++ch) {
        EXPECT_LE(m.mean(ch), 1.0 + 5 * m.se(ch) + 1e-5) << c.name << " wo.z " << wo.z;
      }
    }
  }
}

TEST(BsdfSampling, WeightIsEvalOverPdfAtTheSampledDirection) {
  const BsdfCases cases;
  for (const BsdfCase& c : cases.all()) {
    const Bsdf bsdf(c.params);
    for (glm::vec3 wo : test_wos(c.two_sided_wo)) {
      std::mt19937_64 rng(11);
      for (int i = 0; i < 2000; ++i) {
        const auto s = bsdf.sample(wo, u01(rng), {u01(rng), u01(rng)});
        if (!s) continue;
        EXPECT_GT(s->pdf, 0.0f);
        EXPECT_NEAR(glm::length(s->wi), 1.0f, 1e-4f) << c.name;
        if (s->delta) {
          EXPECT_FALSE(bsdf.has_smooth_lobe() && c.params.type != MaterialType::plastic) << c.name;
          continue;
        }
        const float pdf = bsdf.pdf(wo, s->wi);
        const glm::vec3 f = bsdf.eval(wo, s->wi);
        ASSERT_NEAR(pdf, s->pdf, 2e-3f * s->pdf + 1e-6f) << c.name << " wo.z " << wo.z;
        for (int ch = 0; ch < 3; ++ch) {
          ASSERT_NEAR(f[ch] / pdf, s->weight[ch], 2e-3f * s->weight[ch] + 1e-6f)
              << c.name << " wo.z " << wo.z << " wi.z " << s->wi.z;
        }
      }
    }
  }
}

TEST(BsdfSampling, SmoothLobesAreReported) {
  const BsdfCases cases;
  for (const BsdfCase& c : cases.all()) {
    const bool delta_only = c.params.type == MaterialType::conductor ||
                            c.params.type == MaterialType::mirror ||
                            c.params.type == MaterialType::glass ||
                            c.params.type == MaterialType::thin_glass;
    EXPECT_EQ(Bsdf(c.params).has_smooth_lobe(), !delta_only) << c.name;
  }
}

TEST(BsdfReciprocity, ReflectionIsSymmetricAndTransmissionScalesByEtaSquared) {
  const BsdfCases cases;
  std::mt19937_64 rng(13);
  for (const BsdfCase& c : cases.all()) {
    const Bsdf bsdf(c.params);
    if (!bsdf.has_smooth_lobe()) continue;
    int nonzero = 0;
    for (int i = 0; i < 4000; ++i) {
      const glm::vec3 a = square_to_uniform_sphere({u01(rng), u01(rng)});
      const glm::vec3 b = square_to_uniform_sphere({u01(rng), u01(rng)});
      if (std::abs(a.z) < 0.02f || std::abs(b.z) < 0.02f) continue;
      // Mitsuba's thin principled transmission is not reciprocal: its microfacet side checks
      // test the camera side's direction and the other's mirror image, which swap unevenly.
      // principled_thin_test.cpp checks it against Mitsuba's values instead.
      if (c.params.type == MaterialType::principled_thin && a.z * b.z < 0) continue;
      // BSDF values without the cosine.
      const glm::vec3 f_ab = bsdf.eval(a, b) / std::abs(b.z);
      const glm::vec3 f_ba = bsdf.eval(b, a) / std::abs(a.z);
      // f(wo, wi) / eta_o^2 = f(wi, wo) / eta_i^2, eta_x the index on x's side (1 outside).
      // A thin sheet has the outside's index on both sides.
      const float inside = c.params.type == MaterialType::principled_thin ? 1.0f : c.params.eta;
      const float eta_a = a.z > 0 ? 1.0f : inside, eta_b = b.z > 0 ? 1.0f : inside;
      for (int ch = 0; ch < 3; ++ch) {
        const float lhs = f_ab[ch] / (eta_a * eta_a), rhs = f_ba[ch] / (eta_b * eta_b);
        // The absolute allowance covers pairs at the critical angle, where 1 - F has an
        // infinite slope and float rounding moves it by 1e-6 (f is O(0.1 .. 10) elsewhere).
        EXPECT_NEAR(lhs, rhs, 1e-3f * std::max(lhs, rhs) + 1e-4f)
            << c.name << " a (" << a.x << ", " << a.y << ", " << a.z << ") b (" << b.x << ", "
            << b.y << ", " << b.z << ")";
      }
      nonzero += f_ab.x > 0;
    }
    EXPECT_GT(nonzero, 100) << c.name << ": the test saw the BSDF";
  }
}

TEST(BsdfExtremes, EveryOutputIsFinite) {
  std::vector<BsdfParams> params;
  BsdfCases owner(/*rough_plastic=*/false);
  for (MaterialType type : {MaterialType::diffuse, MaterialType::mirror, MaterialType::glass,
                            MaterialType::conductor, MaterialType::rough_conductor,
                            MaterialType::rough_glass, MaterialType::thin_glass,
                            MaterialType::plastic, MaterialType::rough_plastic,
                            MaterialType::pplastic, MaterialType::polarizer}) {
    for (auto dist : {MicrofacetDistribution::beckmann, MicrofacetDistribution::ggx}) {
      for (float alpha : {1e-4f, 1e-3f, 1.0f}) {
        for (float eta : {1.0f, 1.0001f, 1.0f / 1.0001f, 1.5f, 4.0f}) {
          for (bool visible : {true, false}) {
            BsdfParams p;
            p.type = type;
            p.distribution = dist;
            p.alpha_u = alpha;
            p.alpha_v = type == MaterialType::rough_plastic ? alpha : 2 * alpha;
            p.eta = eta;
            p.sample_visible = visible;
            p.conductor_eta = glm::vec3(eta);
            p.conductor_k = glm::vec3(0.0f);  // k = 0: a conductor that is a dielectric
            if (type == MaterialType::rough_plastic) {
              // Each table costs ~0.25 s: the extreme corners only.
              const bool corner = (dist == MicrofacetDistribution::beckmann && alpha == 1e-4f) ||
                                  (dist == MicrofacetDistribution::ggx && alpha == 1.0f);
              if (!corner || !visible || eta == 1.5f || eta <= 1) continue;
              p = owner.with_table(p);
            }
            params.push_back(p);
          }
        }
      }
    }
  }
  std::vector<glm::vec3> wos = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, -1, 0}};
  for (float z : {1e-7f, 1e-4f, 0.01f, 0.9999f}) {
    const float s = std::sqrt(1 - z * z);
    wos.push_back({s * 0.6f, s * 0.8f, z});
    wos.push_back({s * 0.6f, -s * 0.8f, -z});
  }
  const float one_minus = 1.0f - 0x1p-24f;
  const std::vector<glm::vec2> us = {{0, 0}, {one_minus, one_minus}, {0.5f, 0.5f}, {0, one_minus},
                                     {one_minus, 0}, {0.25f, 0.75f}, {1e-7f, 0.5f}};
  for (const BsdfParams& p : params) {
    const Bsdf bsdf(p);
    for (glm::vec3 wo : wos) {
      for (glm::vec3 wi : wos) {
        ASSERT_TRUE(finite(bsdf.eval(wo, wi))) << int(p.type) << " alpha " << p.alpha_u;
        ASSERT_TRUE(std::isfinite(bsdf.pdf(wo, wi))) << int(p.type);
        ASSERT_GE(bsdf.pdf(wo, wi), 0.0f);
      }
      for (glm::vec2 u : us) {
        for (float u_lobe : {0.0f, 0.5f, one_minus}) {
          const auto s = bsdf.sample(wo, u_lobe, u);
          if (!s) continue;
          ASSERT_TRUE(finite(s->weight) && finite(s->wi) && std::isfinite(s->pdf)) << int(p.type);
          ASSERT_TRUE(s->pdf > 0 && s->weight.x >= 0 && s->eta > 0)
              << int(p.type) << " eta " << p.eta << " alpha " << p.alpha_u << " wo.z " << wo.z
              << " weight " << s->weight.x << " pdf " << s->pdf;
        }
      }
    }
  }
}

TEST(BsdfExtremes, RoughPlasticWithoutItsTableIsAnError) {
  BsdfParams p;
  p.type = MaterialType::rough_plastic;
  EXPECT_THROW(Bsdf{p}, std::invalid_argument);
  const RoughPlasticTable other = make_rough_plastic_table(p.distribution, 0.3f, p.eta);
  p.rough_plastic = &other;
  EXPECT_THROW(Bsdf{p}, std::invalid_argument);
}

TEST(Fresnel, ConductorMatchesClosedFormsAtNormalIncidenceAndTheDielectricWhenKIsZero) {
  for (float n : {0.2f, 1.0f, 1.5f, 3.0f}) {
    for (float k : {0.0f, 1.0f, 3.9f}) {
      const float expected = ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
      EXPECT_NEAR(fresnel_conductor(1.0f, glm::vec3(n), glm::vec3(k)).x, expected, 1e-5f);
    }
  }
  for (float c = 0.0f; c <= 1.0f; c += 0.05f) {
    EXPECT_NEAR(fresnel_conductor(c, glm::vec3(1.5f), glm::vec3(0.0f)).y,
                fresnel_dielectric_signed(c, 1.5f).r, 1e-5f);
  }
  EXPECT_NEAR(fresnel_conductor(0.3f, glm::vec3(0.0f), glm::vec3(1.0f)).z, 1.0f, 1e-6f);
}

TEST(Fresnel, SignedDielectricAgreesWithTheOneSidedForm) {
  for (float eta : {1.0001f, 1.33f, 1.5f, 2.4f}) {
    for (float c = 0.0f; c <= 1.0f; c += 0.05f) {
      float cos_t;
      const float r = fresnel_dielectric(c, eta, &cos_t);
      const DielectricFresnel out = fresnel_dielectric_signed(c, eta);
      EXPECT_NEAR(out.r, r, 1e-5f);
      EXPECT_NEAR(out.cos_theta_t, -cos_t, 1e-5f);
      if (c == 0.0f) continue;  // -0.0 counts as the outside, as in Mitsuba
      const DielectricFresnel in = fresnel_dielectric_signed(-c, eta);
      EXPECT_NEAR(in.r, fresnel_dielectric(c, 1.0f / eta, &cos_t), 1e-5f);
      EXPECT_EQ(in.eta_it, 1.0f / eta);
    }
  }
}

TEST(Fresnel, DiffuseReflectanceFitIsTheHemisphericalAverage) {
  // 2 * integral of F(cos) cos dcos, against the fits' documented accuracy.
  for (float eta : {1.0f / 1.5f, 1.0f / 1.33f, 1.33f, 1.5f, 1.9f}) {
    double sum = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
      const float c = (i + 0.5f) / n;
      sum += 2.0 * fresnel_dielectric_signed(c, eta).r * c / n;
    }
    EXPECT_NEAR(fresnel_diffuse_reflectance(eta), sum, 0.01 * sum) << "eta " << eta;
  }
  // The plastics' internal reflectance stays below 1 and accurate for any index.
  for (float eta : {1.0001f, 1.5f, 2.0f, 3.0f, 4.0f, 8.0f}) {
    double sum = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
      const float c = (i + 0.5f) / n;
      sum += 2.0 * fresnel_dielectric_signed(-c, eta).r * c / n;  // from inside the coating
    }
    // 0.002: the fit's absolute error near eta = 1, where the reflectance itself is ~0.
    EXPECT_NEAR(plastic_internal_reflectance(eta), sum, 0.01 * sum + 0.002) << "eta " << eta;
    EXPECT_LT(plastic_internal_reflectance(eta), 1.0f);
  }
}

}  // namespace
}  // namespace tessera::test
