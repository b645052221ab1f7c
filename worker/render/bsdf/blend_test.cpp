// Mitsuba's blendbsdf: point values of eval() and pdf() against Mitsuba 3's (the table
// mitsuba_blend.txt that mitsuba_blend.py made), a nested blend included, and the albedo of
// blends of a perfectly specular lobe with a smooth one against Mitsuba's sample()
// (mitsuba_blend_albedo.txt). The chi-square, sampling-consistency, reciprocity and furnace
// tests over bsdf_test_cases.h cover its smooth blends too.
#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "render/bsdf/albedo_estimate.h"
#include "render/bsdf/bsdf.h"
#include "render/bsdf/bsdf_test_cases.h"

namespace tessera::test {
namespace {

/// mitsuba_blend.py's ALBEDO_CASES: the two BSDFs of case `name` (a blend of a perfectly
/// specular lobe with a smooth one, or of two smooth ones), at `weight`; `tables` owns the
/// rough plastic's table.
BsdfParams albedo_case(const std::string& name, float weight, BsdfCases& tables) {
  BsdfParams diffuse;
  diffuse.reflectance = {0.7f, 0.5f, 0.3f};
  BsdfParams black_plastic;  // bsdf_blendbsdf.xml's
  black_plastic.type = MaterialType::rough_plastic;
  black_plastic.distribution = MicrofacetDistribution::ggx;
  black_plastic.alpha_u = black_plastic.alpha_v = 0.3f;
  black_plastic.reflectance = glm::vec3(0.0f);
  black_plastic.eta = 1.49f / 1.000277f;  // polypropylene / air, Mitsuba's defaults
  BsdfParams smooth_metal;
  smooth_metal.type = MaterialType::conductor;
  smooth_metal.conductor_eta = {0.2f, 0.9f, 1.1f};
  smooth_metal.conductor_k = {3.9f, 2.4f, 2.2f};
  BsdfParams smooth_glass;
  smooth_glass.type = MaterialType::glass;
  smooth_glass.eta = 1.5f;
  BsdfParams plastic;
  plastic.type = MaterialType::plastic;
  plastic.eta = 1.5f;
  plastic.reflectance = {0.8f, 0.5f, 0.2f};
  BsdfParams p;
  p.type = MaterialType::blend;
  p.blend_weight = weight;
  if (name == "plastic+conductor") {
    p.blend = {tables.with_table(black_plastic), smooth_metal};
  } else if (name == "diffuse+glass") {
    p.blend = {diffuse, smooth_glass};
  } else if (name == "diffuse+plastic") {
    p.blend = {diffuse, plastic};
  } else if (name == "metal+diffuse") {
    p = mitsuba_blend_cases()[0];
    p.blend_weight = weight;
  } else {
    ADD_FAILURE() << "unknown case " << name;
  }
  return p;
}

TEST(BlendEval, MatchesMitsuba3PointValues) {
  const std::string path = std::string(TESSERA_SOURCE_DIR) + "/worker/render/bsdf/mitsuba_blend.txt";
  std::ifstream in(path);
  ASSERT_TRUE(in) << "cannot read " << path;
  const std::vector<BsdfParams> cases = mitsuba_blend_cases();
  std::string text;
  int rows = 0, nonzero = 0;
  for (int line = 1; std::getline(in, text); ++line) {
    if (text.empty() || text[0] == '#') continue;
    std::istringstream s(text);
    size_t index = 0;
    glm::vec3 wo, wi, expected;
    float expected_pdf = 0;
    s >> index >> wo.x >> wo.y >> wo.z >> wi.x >> wi.y >> wi.z >> expected.x >> expected.y >>
        expected.z >> expected_pdf;
    ASSERT_TRUE(s && index < cases.size()) << path << ": line " << line;
    const Bsdf bsdf(cases[index]);
    const glm::vec3 f = bsdf.eval(wo, wi);
    const std::string where = "mitsuba_blend.txt line " + std::to_string(line);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(f[c], expected[c], 2e-4f * expected[c] + 1e-6f) << where << " channel " << c;
    }
    EXPECT_NEAR(bsdf.pdf(wo, wi), expected_pdf, 2e-4f * expected_pdf + 1e-6f) << where << " pdf";
    ++rows;
    nonzero += expected.x > 0;
  }
  EXPECT_EQ(rows, 36);
  EXPECT_GE(nonzero, 20);
}

TEST(BlendAlbedo, MatchesMitsuba3WithPerfectlySpecularLobesToo) {
  // A specular sample gets Mitsuba's weight, (w F + (1 - w) f_other) / (w + (1 - w) pdf_other):
  // at w = 0.5 bsdf_blendbsdf.xml's blend reflects ~0.27 where (1 - w) first + w second would
  // be ~0.49. Tessera's blend was that much brighter before it weighted as Mitsuba.
  const std::string path =
      std::string(TESSERA_SOURCE_DIR) + "/worker/render/bsdf/mitsuba_blend_albedo.txt";
  std::ifstream in(path);
  ASSERT_TRUE(in) << "cannot read " << path;
  BsdfCases tables(/*rough_plastic=*/false);
  std::string text;
  int rows = 0;
  double worst = 0;
  for (int line = 1; std::getline(in, text); ++line) {
    if (text.empty() || text[0] == '#') continue;
    std::istringstream s(text);
    std::string name;
    float weight = 0, cos_theta_o = 0;
    glm::dvec3 expected, expected_se;
    s >> name >> weight >> cos_theta_o >> expected.x >> expected.y >> expected.z >>
        expected_se.x >> expected_se.y >> expected_se.z;
    ASSERT_TRUE(s) << path << ": line " << line << ": expected 9 columns";
    const Bsdf bsdf(albedo_case(name, weight, tables));
    const AlbedoEstimate ours = grid_albedo(bsdf, albedo_wo(cos_theta_o), line, true);
    worst = std::max(worst, expect_albedo_near(ours, expected, expected_se,
                                               "mitsuba_blend_albedo.txt line " +
                                                   std::to_string(line) + " (" + name + ")"));
    ++rows;
  }
  EXPECT_EQ(rows, 18);
  std::cout << rows << " rows, largest relative difference " << worst << "\n";
}

TEST(BlendSample, WeightsAtTheEndsPickOneBsdf) {
  // weight 0 is the first BSDF alone, weight 1 the second, whatever u_lobe is.
  std::vector<BsdfParams> cases = mitsuba_blend_cases();
  for (float weight : {0.0f, 1.0f}) {
    BsdfParams p = cases[0];
    p.blend_weight = weight;
    const Bsdf blend(p), alone(p.blend[weight == 0.0f ? 0 : 1]);
    for (float u_lobe : {0.0f, 0.5f, 1.0f - 0x1p-24f}) {
      const glm::vec3 wo(0.3f, 0.1f, std::sqrt(0.9f));
      const auto s = blend.sample(wo, u_lobe, {0.3f, 0.7f});
      const auto t = alone.sample(wo, 0.5f, {0.3f, 0.7f});
      ASSERT_EQ(s.has_value(), t.has_value());
      if (!s) continue;
      EXPECT_NEAR(s->pdf, t->pdf, 1e-5f * t->pdf);
      EXPECT_NEAR(s->weight.x, t->weight.x, 1e-5f * t->weight.x);
    }
  }
}

}  // namespace
}  // namespace tessera::test
