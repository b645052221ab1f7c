// Mitsuba's principled BSDF: point values of eval() and pdf() against Mitsuba 3's (the table
// mitsuba_principled.txt that mitsuba_principled.py made), its energy bounds, and finite
// values at the extremes of every parameter. The chi-square, sampling-consistency,
// reciprocity and furnace tests over bsdf_test_cases.h cover it too.
#include <cmath>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "render/bsdf/albedo_estimate.h"
#include "render/bsdf/bsdf.h"
#include "render/bsdf/bsdf_test_cases.h"
#include "render/bsdf/chi_square.h"

namespace tessera::test {
namespace {


TEST(PrincipledEval, MatchesMitsuba3PointValues) {
  const std::string path =
      std::string(TESSERA_SOURCE_DIR) + "/worker/render/bsdf/mitsuba_principled.txt";
  std::ifstream in(path);
  ASSERT_TRUE(in) << "cannot read " << path;
  std::string text;
  int rows = 0, nonzero = 0, transmitted = 0;
  double worst = 0;
  for (int line = 1; std::getline(in, text); ++line) {
    if (text.empty() || text[0] == '#') continue;
    std::istringstream s(text);
    BsdfParams p;
    p.type = MaterialType::principled;
    PrincipledInputs& q = p.principled;
    glm::vec3 wo, wi, expected;
    float expected_pdf = 0;
    s >> p.reflectance.x >> p.reflectance.y >> p.reflectance.z >> q.roughness >> q.anisotropic >>
        q.metallic >> q.spec_trans >> q.spec_tint >> q.sheen >> q.sheen_tint >> q.flatness >>
        q.clearcoat >> q.clearcoat_gloss >> p.eta >> q.main_specular_sampling_rate >>
        q.clearcoat_sampling_rate >> q.diffuse_reflectance_sampling_rate >> wo.x >> wo.y >> wo.z >>
        wi.x >> wi.y >> wi.z >> expected.x >> expected.y >> expected.z >> expected_pdf;
    ASSERT_TRUE(s) << path << ": line " << line << ": expected 27 columns";
    q.transmits = q.spec_trans != 0;
    const Bsdf bsdf(p);
    const glm::vec3 f = bsdf.eval(wo, wi);
    const float pdf = bsdf.pdf(wo, wi);
    const std::string where = "mitsuba_principled.txt line " + std::to_string(line);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(f[c], expected[c], 2e-4f * expected[c] + 1e-6f) << where << " channel " << c;
      worst = std::max(worst, std::abs(double(f[c]) - expected[c]) / std::max(expected[c], 1e-3f));
    }
    EXPECT_NEAR(pdf, expected_pdf, 2e-4f * expected_pdf + 1e-6f) << where << " pdf";
    worst = std::max(worst, std::abs(double(pdf) - expected_pdf) / std::max(expected_pdf, 1e-3f));
    ++rows;
    nonzero += expected.x > 0;
    transmitted += expected.x > 0 && wo.z * wi.z < 0;
  }
  EXPECT_GE(rows, 96);
  EXPECT_GE(nonzero, 50);
  EXPECT_GE(transmitted, 5);
  std::cout << rows << " rows, largest relative difference " << worst << "\n";
}

/// Reads the principled parameters of a row of mitsuba_principled*.txt (17 columns).
bool read_params(std::istream& s, BsdfParams* p) {
  p->type = MaterialType::principled;
  PrincipledInputs& q = p->principled;
  s >> p->reflectance.x >> p->reflectance.y >> p->reflectance.z >> q.roughness >> q.anisotropic >>
      q.metallic >> q.spec_trans >> q.spec_tint >> q.sheen >> q.sheen_tint >> q.flatness >>
      q.clearcoat >> q.clearcoat_gloss >> p->eta >> q.main_specular_sampling_rate >>
      q.clearcoat_sampling_rate >> q.diffuse_reflectance_sampling_rate;
  q.transmits = q.spec_trans != 0;
  return bool(s);
}

TEST(PrincipledAlbedo, MatchesMitsuba3WithinOnePercent) {
  // Mitsuba's principled is not energy conserving everywhere (retro-reflection, sheen and the
  // clear coat are added on top): the rows above 1 check that Tessera gains exactly as much.
  const std::string path =
      std::string(TESSERA_SOURCE_DIR) + "/worker/render/bsdf/mitsuba_principled_albedo.txt";
  std::ifstream in(path);
  ASSERT_TRUE(in) << "cannot read " << path;
  std::string text;
  int rows = 0, above_one = 0;
  double worst = 0;
  for (int line = 1; std::getline(in, text); ++line) {
    if (text.empty() || text[0] == '#') continue;
    std::istringstream s(text);
    BsdfParams p;
    float cos_theta_o = 0;
    glm::dvec3 expected, expected_se;
    ASSERT_TRUE(read_params(s, &p)) << path << ": line " << line;
    s >> cos_theta_o >> expected.x >> expected.y >> expected.z >> expected_se.x >> expected_se.y >>
        expected_se.z;
    ASSERT_TRUE(s) << path << ": line " << line << ": expected 24 columns";
    const AlbedoEstimate ours = grid_albedo(Bsdf(p), albedo_wo(cos_theta_o), line, true);
    worst = std::max(worst, expect_albedo_near(ours, expected, expected_se,
                                               "mitsuba_principled_albedo.txt line " +
                                                   std::to_string(line)));
    ++rows;
    above_one += expected.x > 1.0;
  }
  EXPECT_GE(rows, 80);
  EXPECT_GE(above_one, 10);
  std::cout << rows << " rows, largest relative difference " << worst << "\n";
}

/// Mean sample weight (energy: without the 1 / eta^2 of radiance transport) over n samples.
double albedo(const Bsdf& bsdf, glm::vec3 wo, int channel, uint64_t seed, int n, double* se) {
  std::mt19937_64 rng(seed);
  double sum = 0, sum2 = 0;
  for (int i = 0; i < n; ++i) {
    const auto s = bsdf.sample(wo, u01(rng), {u01(rng), u01(rng)});
    const double e = s ? double(s->weight[channel]) * s->eta * s->eta : 0.0;
    sum += e;
    sum2 += e * e;
  }
  const double mean = sum / n;
  *se = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
  return mean;
}

TEST(PrincipledFurnace, SpecularLobesConserveEnergy) {
  // The microfacet lobes scatter once, so they lose energy and never gain it: a white metal,
  // and white glass from both sides, at any roughness, stay at or below 1.
  uint64_t seed = 1;
  for (float roughness : {0.0f, 0.05f, 0.3f, 0.7f, 1.0f}) {
    for (float eta : {1.5f, 1.0f / 1.5f, 1.0001f}) {
      BsdfParams metal;
      metal.type = MaterialType::principled;
      metal.reflectance = glm::vec3(1.0f);
      metal.eta = eta;
      metal.principled.roughness = roughness;
      metal.principled.metallic = 1;
      BsdfParams glass = metal;
      glass.principled.metallic = 0;
      glass.principled.spec_trans = 1;
      glass.principled.transmits = true;
      for (const BsdfParams& p : {metal, glass}) {
        const Bsdf bsdf(p);
        for (glm::vec3 wo : test_wos(p.principled.transmits)) {
          double se;
          const double a = albedo(bsdf, wo, 0, seed++, 20000, &se);
          EXPECT_LE(a, 1.0 + 5 * se + 1e-4)
              << "roughness " << roughness << " eta " << eta << " metallic "
              << p.principled.metallic << " wo.z " << wo.z;
        }
      }
    }
  }
}

TEST(PrincipledFurnace, SmoothWhiteMetalIsLossless) {
  // roughness 0 is GGX alpha 0.001: a mirror with Schlick's F = 1 for base_color 1.
  BsdfParams p;
  p.type = MaterialType::principled;
  p.reflectance = glm::vec3(1.0f);
  p.principled.roughness = 0;
  p.principled.metallic = 1;
  const Bsdf bsdf(p);
  for (glm::vec3 wo : test_wos(false)) {
    if (wo.z < 0.1f) continue;  // single scattering loses energy at grazing even when smooth
    double se;
    EXPECT_NEAR(albedo(bsdf, wo, 1, 5, 20000, &se), 1.0, 0.002) << "wo.z " << wo.z;
  }
}

TEST(PrincipledExtremes, EveryOutputIsFinite) {
  std::vector<BsdfParams> params;
  for (float roughness : {0.0f, 1e-3f, 1.0f}) {
    for (float eta : {1.0f, 1.0001f, 1.0f / 1.0001f, 1.5f, 4.0f}) {
      for (float w : {0.0f, 1.0f}) {
        for (bool transmits : {false, true}) {
          BsdfParams p;
          p.type = MaterialType::principled;
          p.eta = eta;
          p.reflectance = glm::vec3(w, 0.5f, 1.0f);
          PrincipledInputs& in = p.principled;
          in.roughness = roughness;
          in.anisotropic = in.metallic = in.spec_tint = in.sheen = in.sheen_tint = w;
          in.flatness = in.clearcoat = in.clearcoat_gloss = w;
          in.spec_trans = transmits ? 1.0f - w * 0.5f : 0.0f;
          in.transmits = transmits;
          params.push_back(p);
          in.main_specular_sampling_rate = w;  // 0: the other lobes only
          in.diffuse_reflectance_sampling_rate = 1 - w;
          params.push_back(p);
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
  int sampled = 0;
  for (const BsdfParams& p : params) {
    const PrincipledBsdf bsdf(p);  // the BSDF itself, without the interface's guards
    for (glm::vec3 wo : wos) {
      for (glm::vec3 wi : wos) {
        ASSERT_TRUE(finite(bsdf.eval(wo, wi))) << "eta " << p.eta;
        const float pdf = bsdf.pdf(wo, wi);
        ASSERT_TRUE(std::isfinite(pdf) && pdf >= 0) << "eta " << p.eta << " pdf " << pdf;
      }
      for (glm::vec2 u : us) {
        for (float u_lobe : {0.0f, 0.3f, 0.6f, one_minus}) {
          const auto s = bsdf.sample(wo, u_lobe, u);
          if (!s) continue;
          ++sampled;
          ASSERT_TRUE(finite(s->weight) && finite(s->wi) && std::isfinite(s->pdf));
          ASSERT_TRUE(s->pdf > 0 && s->weight.x >= 0 && s->eta > 0)
              << "eta " << p.eta << " roughness " << p.principled.roughness << " wo.z " << wo.z;
        }
      }
    }
  }
  EXPECT_GT(sampled, 1000);
}

}  // namespace
}  // namespace tessera::test
