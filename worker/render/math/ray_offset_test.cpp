#include "render/math/ray_offset.h"

#include <bit>
#include <cstdint>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "render/sampling/sampler.h"

namespace tessera {
namespace {

/// The branch-free step must give next_float_up / next_float_down's bits for every value,
/// NaN payloads, zeros, subnormals and infinities included.
TEST(RayOffset, NextFloatAwayMatchesUpAndDown) {
  constexpr float inf = std::numeric_limits<float>::infinity();
  std::vector<float> values = {0.0f, -0.0f, inf, -inf, std::numeric_limits<float>::quiet_NaN(),
                               std::numeric_limits<float>::denorm_min(),
                               -std::numeric_limits<float>::denorm_min(),
                               std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(),
                               std::numeric_limits<float>::min(), 1.0f, -1.0f};
  for (uint32_t i = 0; i < 200000; ++i) values.push_back(std::bit_cast<float>(uint32_t(mix64(i))));
  const float offsets[] = {1.0f, 1e-30f, inf, -1.0f, -1e-30f, -inf, 0.0f, -0.0f,
                           std::numeric_limits<float>::quiet_NaN()};
  for (const float v : values) {
    for (const float offset : offsets) {
      const float expected = offset > 0 ? next_float_up(v) : offset < 0 ? next_float_down(v) : v;
      ASSERT_EQ(std::bit_cast<uint32_t>(next_float_away(v, offset)), std::bit_cast<uint32_t>(expected))
          << "v bits " << std::bit_cast<uint32_t>(v) << ", offset " << offset;
    }
  }
}

/// The spawned origin lies strictly on the side of the surface the direction points to, past
/// the error box, on both sides and for normals off the axes.
TEST(RayOffset, OriginLeavesTheErrorBoxOnTheSideOfW) {
  const SurfacePoint sp{{1.0f, -2.0f, 3.0f}, {1e-6f, 1e-6f, 1e-6f}, glm::normalize(glm::vec3(1, 2, -2))};
  for (const float side : {1.0f, -1.0f}) {
    const glm::vec3 o = offset_ray_origin(sp, side * sp.ng);
    const float distance = glm::dot(o - sp.p, sp.ng) * side;
    EXPECT_GT(distance, glm::dot(glm::abs(sp.ng), sp.p_error) * 0.99f);
  }
}

}  // namespace
}  // namespace tessera
