// Light picking: picks follow pmf() (chi-square over the lights), the probabilities sum to 1,
// nothing is picked where no light can reach, power picking beyond kMaxPerPoint lights.
#include "render/light/light_picker.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "render/light/light_test_support.h"

namespace tessera {
namespace {

/// A one-sided square light of side 1 and power phi centred at c, facing w.
LightBounds square(glm::vec3 c, glm::vec3 w, double phi) {
  LightBounds b;
  b.center = c;
  b.radius = std::sqrt(0.5f);
  b.phi = phi;
  b.w = w;
  b.cos_theta_o = 1;
  return b;
}

LightBounds point(glm::vec3 p, double phi) {
  LightBounds b;
  b.center = p;
  b.phi = phi;
  return b;
}

TEST(LightPicker, PicksFollowThePmfChiSquare) {
  std::vector<LightBounds> bounds = {square({0, 2, 0}, {0, -1, 0}, 10),
                                     square({3, 1, 0}, {-1, 0, 0}, 4), point({-1, 1, 1}, 2),
                                     point({0, 0.5f, -4}, 30)};
  LightBounds sky;
  sky.infinite = true;
  sky.phi = 0.3;
  bounds.push_back(sky);
  const LightPicker picker(bounds, {10, 4, 2, 30, 1});
  test::UniformFloats u(61);
  for (const SurfacePoint ref : {SurfacePoint{{0, 0, 0}, {0, 0, 0}, {0, 1, 0}},
                                 SurfacePoint{{2.5f, 1, 0.2f}, {0, 0, 0}, {-1, 0, 0}},
                                 SurfacePoint{{-1, 0.5f, 0.5f}, {0, 0, 0}, {0, 0, 1}}}) {
    std::vector<double> expected(bounds.size());
    double sum = 0;
    for (uint32_t i = 0; i < bounds.size(); ++i) {
      expected[i] = picker.pmf(i, ref);
      sum += expected[i];
      EXPECT_GT(expected[i], 0.0) << i;
    }
    EXPECT_NEAR(sum, 1.0, 1e-6);
    const int n = 50000;
    std::vector<double> observed(bounds.size(), 0.0);
    for (int k = 0; k < n; ++k) {
      float pmf = 0;
      const uint32_t i = picker.pick(u.next(), ref, &pmf);
      ASSERT_LT(i, bounds.size());
      ASSERT_EQ(pmf, picker.pmf(i, ref));  // bit for bit
      observed[i] += 1;
    }
    double chi2 = 0;
    for (size_t i = 0; i < bounds.size(); ++i) {
      const double e = expected[i] * n;
      chi2 += (observed[i] - e) * (observed[i] - e) / e;
    }
    EXPECT_GT(test::chi_square_p_value(chi2, int(bounds.size()) - 1), test::kChiSquareLevel)
        << "chi2 " << chi2;
  }
}

TEST(LightPicker, TheSumOfAPickGivesThePmfBitForBit) {
  // pmf(i, ref, sum) with the sum pick() reported at ref weighs one light; it must give the
  // very bits of pmf(i, ref), which weighs all of them, and of the pick's own pmf.
  std::vector<LightBounds> bounds;
  for (int i = 0; i < 7; ++i) {
    bounds.push_back(i % 2 ? square({float(i) - 3, 2, 0.5f * float(i)}, {0, -1, 0}, 1.0 + i)
                           : point({float(i) - 3, 1, -1}, 2.0 + i));
  }
  const LightPicker picker(bounds, {1, 2, 3, 4, 5, 6, 7});
  test::UniformFloats u(62);
  for (int k = 0; k < 2000; ++k) {
    const SurfacePoint ref{{6 * u.next() - 3, 3 * u.next() - 1, 6 * u.next() - 3},
                           {0, 0, 0},
                           {0, 1, 0}};
    float pmf = 0, sum = LightPicker::kUnknownSum;
    const uint32_t i = picker.pick(u.next(), ref, &pmf, &sum);
    ASSERT_EQ(sum, picker.importance_sum(ref));
    if (!(pmf > 0)) continue;
    ASSERT_EQ(pmf, picker.pmf(i, ref, sum));
    for (uint32_t j = 0; j < bounds.size(); ++j) {
      ASSERT_EQ(picker.pmf(j, ref, sum), picker.pmf(j, ref)) << j;
    }
  }
  // Picking by power: no sum, the same pmf either way.
  const LightPicker by_power({bounds[0]}, {1});
  float pmf = 0, sum = 0;
  by_power.pick(0.5f, SurfacePoint{}, &pmf, &sum);
  EXPECT_EQ(sum, LightPicker::kUnknownSum);
  EXPECT_EQ(by_power.pmf(0, SurfacePoint{}, sum), 1.0f);
}

TEST(LightPicker, PicksNothingWhereNoLightCanReach) {
  // Two one-sided squares facing up, the point far below both.
  const LightPicker picker({square({0, 0, 0}, {0, 1, 0}, 1), square({2, 0, 0}, {0, 1, 0}, 1)},
                           {1, 1});
  const SurfacePoint below{{1, -5, 0}, {0, 0, 0}, {0, 1, 0}};
  float pmf = 1;
  picker.pick(0.5f, below, &pmf);
  EXPECT_EQ(pmf, 0.0f);
  EXPECT_EQ(picker.pmf(0, below), 0.0f);
  EXPECT_EQ(picker.pmf(1, below), 0.0f);
  // Above them, in their plane and (the cosine at the point being 0) beside them edge-on.
  for (const SurfacePoint ref : {SurfacePoint{{1, 5, 0}, {0, 0, 0}, {0, 1, 0}},
                                 SurfacePoint{{9, 0, 0}, {0, 0, 0}, {0, 1, 0}}}) {
    EXPECT_GT(picker.pmf(0, ref), 0.0f);
    EXPECT_GT(picker.pmf(1, ref), 0.0f);
  }
}

TEST(LightPicker, OneLightIsPickedWithProbabilityExactlyOne) {
  // 1 + 3 * 2^-26 rounds down to float, so its weight over the double sum of weights is
  // 1 - 2^-26 before rounding to float: 1 - 2^-24, not 1, from the distribution by power.
  for (const double power : {1.0 + 3.0 * 0x1p-26, 0.7, 1e-30, 0.0}) {
    const LightPicker picker({point({0, 1, 0}, power)}, {power});
    for (const float u : {0.0f, 0.5f, 0x1.fffffep-1f}) {
      float pmf = 0, sum = 0;
      EXPECT_EQ(picker.pick(u, SurfacePoint{{0, 0, 0}, {0, 0, 0}, {0, 1, 0}}, &pmf, &sum), 0u);
      EXPECT_EQ(pmf, 1.0f) << power;
      EXPECT_EQ(sum, LightPicker::kUnknownSum);
    }
    EXPECT_EQ(picker.pmf(0, SurfacePoint{}), 1.0f) << power;
  }
}

TEST(LightPicker, BeyondSixteenLightsPicksByPower) {
  std::vector<LightBounds> bounds;
  std::vector<double> powers;
  for (int i = 0; i < int(LightPicker::kMaxPerPoint) + 1; ++i) {
    bounds.push_back(point({float(i), 0, 0}, 1.0 + i));
    powers.push_back(1.0 + i);
  }
  const LightPicker picker(bounds, powers);
  const double total = 17 * 18 / 2.0;
  for (const SurfacePoint ref : {SurfacePoint{{0, 1, 0}, {0, 0, 0}, {0, 1, 0}},
                                 SurfacePoint{{16, 1, 0}, {0, 0, 0}, {0, 1, 0}}}) {
    for (uint32_t i = 0; i < bounds.size(); ++i) {
      EXPECT_NEAR(picker.pmf(i, ref), (1.0 + i) / total, 1e-6);
    }
  }
}

}  // namespace
}  // namespace tessera
