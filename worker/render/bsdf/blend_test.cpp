// Mitsuba's blendbsdf: point values of eval() and pdf() against Mitsuba 3's (the table
// mitsuba_blend.txt that mitsuba_blend.py made), a nested blend included. The chi-square,
// sampling-consistency, reciprocity and furnace tests over bsdf_test_cases.h cover it too.
#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "render/bsdf/bsdf.h"

namespace tessera::test {
namespace {

/// The blends of mitsuba_blend.py's CASES, in order.
std::vector<BsdfParams> mitsuba_blend_cases() {
  BsdfParams diffuse;
  diffuse.reflectance = {0.7f, 0.5f, 0.3f};
  BsdfParams metal;
  metal.type = MaterialType::rough_conductor;
  metal.distribution = MicrofacetDistribution::ggx;
  metal.alpha_u = metal.alpha_v = 0.2f;
  metal.conductor_eta = {0.2f, 0.9f, 1.1f};
  metal.conductor_k = {3.9f, 2.4f, 2.2f};
  BsdfParams glass;
  glass.type = MaterialType::rough_glass;
  glass.distribution = MicrofacetDistribution::beckmann;
  glass.alpha_u = glass.alpha_v = 0.3f;
  glass.eta = 1.5f;
  BsdfParams principled_metal;
  principled_metal.type = MaterialType::principled;
  principled_metal.reflectance = {0.9f, 0.6f, 0.3f};
  principled_metal.eta = 1.5f;
  principled_metal.principled.metallic = 1.0f;
  principled_metal.principled.roughness = 0.4f;
  auto blend = [](float weight, const BsdfParams& a, const BsdfParams& b) {
    BsdfParams p;
    p.type = MaterialType::blend;
    p.blend_weight = weight;
    p.blend = {a, b};
    return p;
  };
  const BsdfParams glass_and_diffuse = blend(0.6f, glass, diffuse);
  return {blend(0.3f, metal, diffuse), glass_and_diffuse,
          blend(0.25f, glass_and_diffuse, principled_metal)};
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
