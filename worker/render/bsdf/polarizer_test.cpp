// Mitsuba's polarizer BSDF as its RGB variants render it: sample() against Mitsuba 3's for the
// same inputs (mitsuba_polarizer.txt, from mitsuba_polarizer.py), the furnace (weight 1/2 of
// the transmittance, never more), and finite values at extreme inputs.
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "render/bsdf/bsdf.h"

namespace tessera::test {
namespace {

BsdfParams polarizer(glm::vec3 transmittance) {
  BsdfParams p;
  p.type = MaterialType::polarizer;
  p.specular_transmittance = transmittance;
  return p;
}

TEST(PolarizerSample, MatchesMitsuba3) {
  std::ifstream in(std::string(TESSERA_SOURCE_DIR) + "/worker/render/bsdf/mitsuba_polarizer.txt");
  ASSERT_TRUE(in) << "cannot read mitsuba_polarizer.txt";
  std::string text;
  int rows = 0, from_below = 0;
  for (int line = 1; std::getline(in, text); ++line) {
    if (text.empty() || text[0] == '#') continue;
    std::istringstream s(text);
    glm::vec3 trans, wo, wi, weight;
    float pdf = 0, delta = 0, eval_max = 0, pdf_pair = 0;
    s >> trans.x >> trans.y >> trans.z >> wo.x >> wo.y >> wo.z >> wi.x >> wi.y >> wi.z >>
        weight.x >> weight.y >> weight.z >> pdf >> delta >> eval_max >> pdf_pair;
    ASSERT_TRUE(s) << "mitsuba_polarizer.txt line " << line << ": expected 16 columns";
    const std::string where = "mitsuba_polarizer.txt line " + std::to_string(line);
    const Bsdf bsdf(polarizer(trans));
    const std::optional<BsdfSample> bs = bsdf.sample(wo, 0.37f, glm::vec2(0.3f, 0.8f));
    ASSERT_TRUE(bs.has_value()) << where;
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(bs->wi[c], wi[c], 1e-6f) << where;
      EXPECT_NEAR(bs->weight[c], weight[c], 1e-6f) << where;
    }
    EXPECT_EQ(bs->pdf, pdf) << where;
    EXPECT_EQ(bs->delta, delta != 0) << where;
    EXPECT_EQ(bs->eta, 1.0f) << where;
    // A delta-only BSDF: nothing for next-event estimation or MIS, as in Mitsuba.
    EXPECT_EQ(eval_max, 0.0f) << where;
    EXPECT_EQ(pdf_pair, 0.0f) << where;
    const glm::vec3 other = -glm::normalize(wo + glm::vec3(0.1f, 0.0f, 0.0f));
    EXPECT_EQ(bsdf.eval(wo, other), glm::vec3(0.0f)) << where;
    EXPECT_EQ(bsdf.pdf(wo, other), 0.0f) << where;
    EXPECT_FALSE(bsdf.has_smooth_lobe());
    ++rows;
    if (wo.z < 0) ++from_below;
  }
  EXPECT_EQ(rows, 48);
  EXPECT_GT(from_below, 0);
}

// Energy: an ideal polarizer passes half of unpolarized light; the weight is exactly
// transmittance / 2 for every direction and random number, so the furnace gives 1/2 for a
// white transmittance and never more than 1.
TEST(PolarizerFurnace, HalfOfTheTransmittanceForEveryDirection) {
  const Bsdf bsdf(polarizer(glm::vec3(1.0f)));
  for (float cos_o : {1.0f, 0.5f, 1e-4f, -1e-4f, -0.7f, -1.0f}) {
    const float sin_o = std::sqrt(std::max(0.0f, 1.0f - cos_o * cos_o));
    const glm::vec3 wo(sin_o * 0.6f, sin_o * 0.8f, cos_o);
    for (float u : {0.0f, 0.5f, 0.999f}) {
      const std::optional<BsdfSample> bs = bsdf.sample(wo, u, glm::vec2(u, 1.0f - u));
      ASSERT_TRUE(bs.has_value()) << "cos " << cos_o;
      EXPECT_EQ(bs->weight, glm::vec3(0.5f)) << "cos " << cos_o;
      EXPECT_EQ(bs->wi, -wo);
      EXPECT_LT(bs->wi.z * wo.z, 0.0f) << "crosses the surface";
    }
  }
}

TEST(PolarizerExtremes, FiniteOrNoSample) {
  // Exactly grazing: no side is crossed, no sample (the integrator ends the path).
  const Bsdf grazing(polarizer(glm::vec3(1.0f)));
  EXPECT_FALSE(grazing.sample(glm::vec3(1.0f, 0.0f, 0.0f), 0.5f, glm::vec2(0.5f)).has_value());
  // Black and large transmittances (textures are not clamped) stay finite.
  for (glm::vec3 t : {glm::vec3(0.0f), glm::vec3(1e30f), glm::vec3(0.0f, 1.0f, 3.0f)}) {
    const Bsdf bsdf(polarizer(t));
    const std::optional<BsdfSample> bs = bsdf.sample(glm::vec3(0.0f, 0.0f, -1.0f), 0.2f, glm::vec2(0.1f));
    ASSERT_TRUE(bs.has_value());
    EXPECT_TRUE(std::isfinite(bs->weight.x) && std::isfinite(bs->weight.y) &&
                std::isfinite(bs->weight.z));
    EXPECT_EQ(bs->weight, 0.5f * t);
  }
}

}  // namespace
}  // namespace tessera::test
