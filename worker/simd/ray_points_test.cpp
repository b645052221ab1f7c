// The dispatched kernel gives the same bits on every instruction set the CPU has, and they are
// the unfused multiply-then-add of the scalar code.
#include "simd/ray_points.h"

#include <bit>
#include <cmath>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <hwy/targets.h>

namespace tessera::simd {
namespace {

struct Batch {
  std::vector<float> ox, oy, oz, dx, dy, dz, t;
};

/// Values spread over many magnitudes and signs, so that rounding the product before the sum
/// (two roundings) and a fused multiply-add (one) give different bits on many lanes.
Batch random_batch(size_t n) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::uniform_int_distribution<int> e(-20, 20);
  Batch b;
  for (std::vector<float>* v : {&b.ox, &b.oy, &b.oz, &b.dx, &b.dy, &b.dz, &b.t}) {
    for (size_t i = 0; i < n; ++i) v->push_back(std::ldexp(u(rng), e(rng)));
  }
  return b;
}

TEST(RayPoints, EveryTargetGivesTheUnfusedScalarBits) {
  const size_t n = 1003;  // not a multiple of any vector width: the tail is exercised too
  const Batch b = random_batch(n);
  std::vector<float> expected(3 * n);
  int fused_differs = 0;
  for (size_t i = 0; i < n; ++i) {
    const float* o[3] = {&b.ox[i], &b.oy[i], &b.oz[i]};
    const float* d[3] = {&b.dx[i], &b.dy[i], &b.dz[i]};
    for (int a = 0; a < 3; ++a) {
      const volatile float td = b.t[i] * *d[a];  // volatile: one rounding after the multiply
      expected[3 * i + a] = *o[a] + td;
      fused_differs += std::fma(b.t[i], *d[a], *o[a]) != expected[3 * i + a];
    }
  }
  ASSERT_GT(fused_differs, 100) << "the inputs do not tell a fused multiply-add apart";

  std::set<std::string> targets;
  for (int64_t target : hwy::SupportedAndGeneratedTargets()) {
    hwy::SetSupportedTargetsForTest(target);
    targets.insert(dispatched_target());
    EXPECT_STREQ(dispatched_target(), hwy::TargetName(target));
    std::vector<float> px(n), py(n), pz(n);
    points_along_rays(b.ox.data(), b.oy.data(), b.oz.data(), b.dx.data(), b.dy.data(), b.dz.data(), b.t.data(),
                      n, px.data(), py.data(), pz.data());
    int differences = 0;
    for (size_t i = 0; i < n; ++i) {
      const float got[3] = {px[i], py[i], pz[i]};
      for (int a = 0; a < 3; ++a) {
        if (std::bit_cast<uint32_t>(got[a]) != std::bit_cast<uint32_t>(expected[3 * i + a]) && ++differences <= 3) {
          ADD_FAILURE() << hwy::TargetName(target) << " lane " << i << " axis " << a << ": " << got[a]
                        << " instead of " << expected[3 * i + a];
        }
      }
    }
    EXPECT_EQ(differences, 0) << hwy::TargetName(target);
  }
  hwy::SetSupportedTargetsForTest(0);
  // On this project's x86-64 machines at least SSE4 and AVX2 are built and run.
  EXPECT_GE(targets.size(), 2u) << "only one instruction set was tested";
}

TEST(RayPoints, OutputsMayAliasTheOrigins) {
  Batch b = random_batch(37);
  const Batch copy = b;
  points_along_rays(b.ox.data(), b.oy.data(), b.oz.data(), b.dx.data(), b.dy.data(), b.dz.data(), b.t.data(),
                    b.ox.size(), b.ox.data(), b.oy.data(), b.oz.data());
  for (size_t i = 0; i < b.ox.size(); ++i) {
    const volatile float td = copy.t[i] * copy.dy[i];
    EXPECT_EQ(b.oy[i], copy.oy[i] + td) << i;
  }
}

}  // namespace
}  // namespace tessera::simd
