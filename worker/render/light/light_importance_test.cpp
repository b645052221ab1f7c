// The float importance kernel: close to LightBounds::importance (the definition, in double)
// wherever that is positive, positive wherever that is, one light alone bit for bit as all of
// them together, and no underflow, overflow or NaN taking a reachable light to 0 at extreme
// scales.
#include "render/light/light_importance.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "render/light/light_test_support.h"

namespace tessera {
namespace {

glm::vec3 unit_vector(test::UniformFloats& u) {
  const float z = 1.0f - 2.0f * u.next(), phi = 2.0f * float(M_PI) * u.next();
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

glm::vec3 point_in_box(test::UniformFloats& u, float size) {
  return {size * (2 * u.next() - 1), size * (2 * u.next() - 1), size * (2 * u.next() - 1)};
}

/// Planar one- and two-sided lights, spheres, points, cones between, spots of emission.
std::vector<LightBounds> random_lights(test::UniformFloats& u, size_t count, bool flat_only) {
  std::vector<LightBounds> lights;
  for (size_t i = 0; i < count; ++i) {
    LightBounds b;
    b.center = point_in_box(u, 3);
    b.phi = 0.1 + 10.0 * u.next();
    const int kind = flat_only ? 0 : int(u.next() * 4);
    if (kind == 0) {  // a planar light
      b.radius = 0.05f + 0.5f * u.next();
      b.w = unit_vector(u);
      b.cos_theta_o = 1;
      b.two_sided = u.next() < 0.3f;
    } else if (kind == 1) {  // a sphere
      b.radius = 0.05f + 0.5f * u.next();
    } else if (kind == 2) {  // a point
      b.radius = 0;
    } else {  // a curved mesh, or a light with a narrower emission
      b.radius = 0.05f + 0.5f * u.next();
      b.w = unit_vector(u);
      b.cos_theta_o = 2 * u.next() - 1;
      b.cos_theta_e = u.next() < 0.5f ? 0.0f : std::cos(0.3f + u.next());
    }
    lights.push_back(b);
  }
  return lights;
}

double max_phi(const std::vector<LightBounds>& lights) {
  double m = 0;
  for (const LightBounds& b : lights) m = std::max(m, b.phi);
  return m;
}

TEST(LightImportance, FloatKernelFollowsTheDoubleDefinition) {
  test::UniformFloats u(1301);
  int compared = 0;
  for (int scene = 0; scene < 40; ++scene) {
    const std::vector<LightBounds> lights = random_lights(u, 1 + size_t(u.next() * 16), false);
    const LightImportance importance(lights);
    const double scale = 1.0 / max_phi(lights);
    for (int k = 0; k < 200; ++k) {
      const glm::vec3 p = point_in_box(u, 4);
      const glm::vec3 n = k % 10 == 0 ? glm::vec3(0.0f) : unit_vector(u);
      float fast[LightImportance::kMaxLights];
      const float sum = importance.evaluate_all(p, n, fast);
      double fast_sum = 0;
      for (size_t i = 0; i < lights.size(); ++i) {
        const double exact = lights[i].importance(p, n) * scale;
        fast_sum += fast[i];
        if (exact > 0) {
          ASSERT_GT(fast[i], 0.0f) << "scene " << scene << " light " << i;
        }
        // Within float rounding of the cosines (1e-4 of the light's phi / d^2), relative 2e-3.
        const double d = std::max(double(glm::length(p - lights[i].center)),
                                  double(lights[i].radius));
        const double scale_i = lights[i].phi * scale / std::max(d * d, 1e-20);
        const double expected = std::clamp(exact, exact > 0 ? 1e-15 : 0.0, 1e15);
        EXPECT_NEAR(fast[i], expected, 2e-3 * expected + 1e-4 * scale_i)
            << "scene " << scene << " light " << i;
        ++compared;
      }
      EXPECT_NEAR(sum, fast_sum, 1e-5 * fast_sum);
    }
  }
  EXPECT_GT(compared, 40000);
}

TEST(LightImportance, OneLightAloneHasTheBitsOfAllTogether) {
  test::UniformFloats u(1302);
  for (int scene = 0; scene < 10; ++scene) {
    const std::vector<LightBounds> lights = random_lights(u, 1 + size_t(u.next() * 16), false);
    const LightImportance importance(lights);
    for (int k = 0; k < 100; ++k) {
      const glm::vec3 p = point_in_box(u, 4), n = unit_vector(u);
      float all[LightImportance::kMaxLights];
      importance.evaluate_all(p, n, all);
      for (uint32_t i = 0; i < lights.size(); ++i) {
        const float one = importance.evaluate(i, p, n);
        ASSERT_EQ(std::memcmp(&one, &all[i], sizeof one), 0) << one << " " << all[i];
      }
    }
  }
}

}  // namespace

// The wavefront kernels' layout (wavefront_kernel.inc): one light at K points at once, in GCC
// vector types of 4, 8 and 16 lanes (here compiled for the baseline; the kernels compile the
// same template for AVX2 and AVX-512). Each lane must have evaluate_all's bits at its point,
// and the lanes' running sum over the lights evaluate_all's sum.
namespace light_importance_lanes_test {

// 32- and 64-byte vectors pass between inlined functions of this file only: GCC's note that
// their ABI would differ without AVX does not apply. (It comes at the end of the translation
// unit, so it is switched off to the end of the file.)
#pragma GCC diagnostic ignored "-Wpsabi"
template <int K>
struct Lanes {
  typedef float F32 __attribute__((vector_size(4 * K)));
  typedef int32_t I32 __attribute__((vector_size(4 * K)));
};

template <int K>
void expect_lanes_have_the_bits_of_each_point(uint64_t seed) {
  using F32 = typename Lanes<K>::F32;
  using I32 = typename Lanes<K>::I32;
  test::UniformFloats u(seed);
  int compared = 0;
  for (int scene = 0; scene < 24; ++scene) {
    // 1 to 16 lights (so up to four blocks), one in three scenes with a light at infinity.
    std::vector<LightBounds> lights = random_lights(u, 1 + size_t(u.next() * 16), false);
    if (scene % 3 == 0) {
      LightBounds sky;
      sky.infinite = true;
      sky.phi = 2.0;
      lights[size_t(u.next() * float(lights.size() - 1))] = sky;
    }
    const LightImportance importance(lights);
    for (int round = 0; round < 40; ++round) {
      glm::vec3 p[K], n[K];
      F32 px, py, pz, nx, ny, nz;
      for (int l = 0; l < K; ++l) {
        // Points near and far (inside a light's bounds too), in media (n = 0) now and then.
        const float size = l % 4 == 0 ? 0.3f : l % 4 == 1 ? 4.0f : l % 4 == 2 ? 40.0f : 4e4f;
        p[l] = point_in_box(u, size);
        n[l] = (round + l) % 7 == 0 ? glm::vec3(0.0f) : unit_vector(u);
        px[l] = p[l].x, py[l] = p[l].y, pz[l] = p[l].z;
        nx[l] = n[l].x, ny[l] = n[l].y, nz[l] = n[l].z;
      }
      const I32 has_n = (nx != 0.0f) | (ny != 0.0f) | (nz != 0.0f);
      F32 total{};
      float lane_values[LightImportance::kMaxLights][K];
      for (uint32_t i = 0; i < uint32_t(lights.size()); ++i) {
        const F32 v = light_importance_detail::importance_lanes<F32, I32>(
            importance.template light_lanes<F32, I32>(i), px, py, pz, nx, ny, nz, has_n);
        std::memcpy(lane_values[i], &v, sizeof v);
        total += v;
      }
      for (int l = 0; l < K; ++l) {
        float all[LightImportance::kMaxLights];
        const float sum = importance.evaluate_all(p[l], n[l], all);
        for (uint32_t i = 0; i < lights.size(); ++i) {
          ASSERT_EQ(std::memcmp(&lane_values[i][l], &all[i], sizeof(float)), 0)
              << K << " lanes, scene " << scene << ", light " << i << ", lane " << l << ": "
              << lane_values[i][l] << " against " << all[i];
          ++compared;
        }
        const float lane_sum = total[l];
        ASSERT_EQ(std::memcmp(&lane_sum, &sum, sizeof sum), 0) << K << " lanes, scene " << scene << ", lane " << l;
      }
    }
  }
  EXPECT_GT(compared, 24 * 40 * K);
}

TEST(LightImportance, ManyPointsAtOnceHaveTheBitsOfEachAlone) {
  expect_lanes_have_the_bits_of_each_point<4>(1311);
  expect_lanes_have_the_bits_of_each_point<8>(1312);
  expect_lanes_have_the_bits_of_each_point<16>(1313);
}

}  // namespace light_importance_lanes_test

namespace {

TEST(LightImportance, ReachableLightsStayPositiveAtExtremeScales) {
  // Powers 1e-30 apart, a light at 1e18, points on a light, far away and next to a point light.
  std::vector<LightBounds> lights(4);
  lights[0].center = {0, 0, 0};
  lights[0].phi = 1e10;
  lights[1].center = {1e18f, 0, 0};
  lights[1].radius = 1;
  lights[1].phi = 1e-20;
  lights[2].center = {0, 1, 0};
  lights[2].radius = 0.5f;
  lights[2].w = {0, -1, 0};
  lights[2].cos_theta_o = 1;
  lights[2].phi = 1;
  lights[3].infinite = true;
  lights[3].phi = 1e-12;
  const LightImportance importance(lights);
  for (const glm::vec3 p : {glm::vec3(0.0f), glm::vec3(1e-30f, 0, 0), glm::vec3(0, 1, 0),
                            glm::vec3(0, 0.5f, 0), glm::vec3(-1e30f, 0, 0),
                            glm::vec3(1e18f, 0, 0)}) {
    float values[LightImportance::kMaxLights];
    const float sum = importance.evaluate_all(p, {0, 1, 0}, values);
    EXPECT_TRUE(std::isfinite(sum)) << p.x;
    for (int i = 0; i < 4; ++i) {
      // Light 2 faces down: above its plane it cannot reach, below it it must.
      if (i == 2 && p.y >= 1) continue;
      EXPECT_GT(values[i], 0.0f) << "light " << i << " at " << p.x << "," << p.y;
      EXPECT_GT(values[i] / sum, 0.0f) << "light " << i;
    }
  }
  // A point above the downward light (by much more than the slack) does not get it.
  float values[LightImportance::kMaxLights];
  importance.evaluate_all({0, 3, 0}, {0, 1, 0}, values);
  EXPECT_EQ(values[2], 0.0f);
}

TEST(LightImportance, PowerZeroIsNeverPicked) {
  std::vector<LightBounds> lights(2);
  lights[0].phi = 0;
  lights[1].center = {1, 0, 0};
  lights[1].phi = 1;
  const LightImportance importance(lights);
  float values[LightImportance::kMaxLights];
  importance.evaluate_all({0, 0, 0}, {0, 1, 0}, values);  // inside light 0's (empty) bounds
  EXPECT_EQ(values[0], 0.0f);
  importance.evaluate_all({0, 2, 0}, {0, 1, 0}, values);
  EXPECT_EQ(values[0], 0.0f);
  EXPECT_GT(values[1], 0.0f);
  EXPECT_THROW(LightImportance(std::vector<LightBounds>(LightImportance::kMaxLights + 1)),
               std::invalid_argument);
}

}  // namespace
}  // namespace tessera
