// Point values of eval() and pdf() against Mitsuba 3's, from the table mitsuba_eval.txt that
// mitsuba_eval.py made: fixed pairs of directions on both sides of the surface, for the rough
// BSDFs (both samplers, anisotropic), the plastics (pplastic as Mitsuba's RGB variants render
// it) and the diffuse BSDF.
#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "render/bsdf/bsdf.h"
#include "render/bsdf/bsdf_test_cases.h"

namespace tessera::test {
namespace {

MaterialType type_of(const std::string& name, int line) {
  if (name == "rough_conductor") return MaterialType::rough_conductor;
  if (name == "rough_glass") return MaterialType::rough_glass;
  if (name == "rough_plastic") return MaterialType::rough_plastic;
  if (name == "plastic") return MaterialType::plastic;
  if (name == "pplastic") return MaterialType::pplastic;
  if (name != "diffuse") ADD_FAILURE() << "mitsuba_eval.txt line " << line << ": unknown " << name;
  return MaterialType::diffuse;
}

TEST(BsdfEval, MatchesMitsuba3PointValues) {
  const std::string path =
      std::string(TESSERA_SOURCE_DIR) + "/worker/render/bsdf/mitsuba_eval.txt";
  std::ifstream in(path);
  ASSERT_TRUE(in) << "cannot read " << path;
  std::string text, header;
  BsdfCases tables(/*rough_plastic=*/false);
  int rows = 0, nonzero = 0;
  double worst = 0;
  for (int line = 1; std::getline(in, text); ++line) {
    if (text.empty()) continue;
    if (text[0] == '#') {
      header += text;
      continue;
    }
    std::istringstream s(text);
    std::string type, dist;
    int nonlinear = 0, visible = 1;
    BsdfParams p;
    glm::vec3 wo, wi, expected;
    float expected_pdf = 0;
    s >> type >> dist >> p.alpha_u >> p.alpha_v >> p.eta >> nonlinear >> visible >> wo.x >> wo.y >>
        wo.z >> wi.x >> wi.y >> wi.z >> expected.x >> expected.y >> expected.z >> expected_pdf;
    ASSERT_TRUE(s) << path << ": line " << line << ": expected 17 columns";
    p.type = type_of(type, line);
    p.distribution = dist == "ggx" ? MicrofacetDistribution::ggx : MicrofacetDistribution::beckmann;
    p.nonlinear = nonlinear != 0;
    p.sample_visible = visible != 0;
    p.conductor_eta = {0.2f, 0.9f, 1.1f};
    p.conductor_k = {3.9f, 2.4f, 2.2f};
    p.reflectance = {0.8f, 0.5f, 0.2f};
    if (p.type == MaterialType::rough_plastic) p = tables.with_table(p);
    const Bsdf bsdf(p);
    const glm::vec3 f = bsdf.eval(wo, wi);
    const float pdf = bsdf.pdf(wo, wi);
    const std::string where = "mitsuba_eval.txt line " + std::to_string(line) + " (" + type + ")";
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(f[c], expected[c], 1e-4f * expected[c] + 1e-6f) << where << " channel " << c;
      worst = std::max(worst, std::abs(double(f[c]) - expected[c]) / std::max(expected[c], 1e-3f));
    }
    EXPECT_NEAR(pdf, expected_pdf, 1e-4f * expected_pdf + 1e-6f) << where << " pdf";
    worst = std::max(worst, std::abs(double(pdf) - expected_pdf) / std::max(expected_pdf, 1e-3f));
    ++rows;
    nonzero += expected.x > 0;
  }
  ASSERT_NE(header.find("conductor eta [0.2, 0.9, 1.1] k [3.9, 2.4, 2.2]"), std::string::npos);
  ASSERT_NE(header.find("reflectance [0.8, 0.5, 0.2]"), std::string::npos);
  EXPECT_GE(rows, 280);
  EXPECT_GE(nonzero, 100);
  std::cout << rows << " rows, largest relative difference " << worst << "\n";
}

}  // namespace
}  // namespace tessera::test
