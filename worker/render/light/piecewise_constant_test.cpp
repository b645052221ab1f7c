// Piecewise-constant distributions: probabilities, empty cells never picked, remapped samples.
#include "render/light/piecewise_constant.h"

#include <gtest/gtest.h>

#include "render/light/light_test_support.h"

namespace tessera {
namespace {

TEST(PiecewiseConstant1D, PicksInProportionAndNeverAnEmptyCell) {
  const PiecewiseConstant1D d({0.0, 1.0, 0.0, 3.0, 0.0, 0.0});
  EXPECT_DOUBLE_EQ(d.total(), 4.0);
  EXPECT_FLOAT_EQ(d.pmf(1), 0.25f);
  EXPECT_FLOAT_EQ(d.pmf(3), 0.75f);
  EXPECT_EQ(d.pmf(5), 0.0f);
  // The extremes of u, including the largest float below 1 (a trailing empty cell must not get it).
  for (float u : {0.0f, 0.2499999f, 0.25f, 0.5f, 0x1.fffffep-1f}) {
    float pmf = 0, remapped = -1;
    const uint32_t i = d.sample_discrete(u, &pmf, &remapped);
    EXPECT_TRUE(i == 1 || i == 3) << "u " << u << " gave cell " << i;
    EXPECT_EQ(pmf, d.pmf(i));
    EXPECT_GE(remapped, 0.0f);
    EXPECT_LT(remapped, 1.0f);
  }
  float pmf = 0, remapped = 0;
  EXPECT_EQ(d.sample_discrete(0.625f, &pmf, &remapped), 3u);
  EXPECT_FLOAT_EQ(remapped, 0.5f);
}

TEST(PiecewiseConstant1D, AllZeroIsEmpty) {
  const PiecewiseConstant1D d({0.0, 0.0});
  EXPECT_TRUE(d.empty());
  EXPECT_EQ(d.pmf(0), 0.0f);
}

TEST(PiecewiseConstant2D, CellFrequenciesFollowTheWeights) {
  const std::vector<double> w = {1, 0, 2, 4, 0, 1};  // 3 x 2
  const PiecewiseConstant2D d(w, 3, 2);
  test::UniformFloats u(31);
  std::vector<int> counts(6, 0);
  const int n = 80000;
  for (int i = 0; i < n; ++i) {
    float pmf = 0;
    glm::vec2 inside;
    const glm::u32vec2 c = d.sample(u.next2(), &pmf, &inside);
    ASSERT_EQ(pmf, d.pmf(c.x, c.y));
    ASSERT_TRUE(inside.x >= 0 && inside.x < 1 && inside.y >= 0 && inside.y < 1);
    ++counts[c.y * 3 + c.x];
  }
  for (int k = 0; k < 6; ++k) {
    const double p = w[k] / 8.0;
    EXPECT_NEAR(counts[k], n * p, 5 * std::sqrt(n * p * (1 - p)) + 1e-9) << "cell " << k;
    EXPECT_FLOAT_EQ(d.pmf(k % 3, k / 3), float(p));
  }
}

}  // namespace
}  // namespace tessera
