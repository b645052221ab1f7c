// Rays spawned off surfaces never hit the surface they leave, at any scene scale (the shape of
// pbrt-v4's Reintersect tests in shapes_test.cpp).
#include <random>

#include <gtest/gtest.h>

#include "sphere_intersector.h"
#include "test_scenes.h"
#include "traceable_scene.h"
#include "warp.h"

namespace tessera {
namespace {

class Reintersect : public ::testing::TestWithParam<double> {};

glm::dvec3 random_point(std::mt19937& rng, double extent) {
  std::uniform_real_distribution<double> u(-extent, extent);
  return {u(rng), u(rng), u(rng)};
}

TEST_P(Reintersect, TrianglesAreNotHitAgain) {
  const double scale = GetParam();
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  int hits_checked = 0;
  for (int trial = 0; trial < 200; ++trial) {
    Scene s;
    const uint32_t m = test::add_diffuse(s, {0.5, 0.5, 0.5});
    // A triangle of size ~scale placed up to 100 sizes from the origin, so the error of its
    // coordinates is large relative to its size.
    const glm::dvec3 base = random_point(rng, 100.0 * scale);
    Shape tri;
    tri.positions = {base + random_point(rng, scale), base + random_point(rng, scale),
                     base + random_point(rng, scale)};
    tri.indices = {{0, 1, 2}};
    tri.material = m;
    s.shapes.push_back(tri);
    const TraceableScene scene(s, 4, 4, "");

    for (int r = 0; r < 20; ++r) {
      // A ray from far away towards a random point on the triangle.
      const glm::vec2 b = square_to_triangle({u(rng), u(rng)});
      const glm::dvec3 target = (1.0 - b.x - b.y) * tri.positions[0] + double(b.x) * tri.positions[1] +
                                double(b.y) * tri.positions[2];
      const glm::dvec3 origin = target + random_point(rng, 10.0 * scale);
      Ray ray{glm::vec3(origin), glm::vec3(target - origin)};
      Hit hit;
      if (!scene.intersect(ray, &hit)) continue;  // grazing miss: nothing to check
      for (int k = 0; k < 20; ++k) {
        const glm::vec3 w = square_to_uniform_sphere({u(rng), u(rng)});
        Ray spawned{offset_ray_origin(hit.sp, w), w};
        Hit again;
        EXPECT_FALSE(scene.intersect(spawned, &again)) << "scale " << scale << " trial " << trial;
        ++hits_checked;
      }
    }
  }
  EXPECT_GT(hits_checked, 20000);
}

TEST_P(Reintersect, SpheresAreNotHitAgainLeavingAndHitOnTheFarSideEntering) {
  const double scale = GetParam();
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::uniform_real_distribution<double> radius(0.05, 1.0);
  int outward = 0, inward = 0;
  for (int trial = 0; trial < 100; ++trial) {
    Scene s;
    const uint32_t m = test::add_material(s, MaterialType::glass);
    const glm::dvec3 center = random_point(rng, 100.0 * scale);
    const double r = radius(rng) * scale;
    s.shapes.push_back(test::sphere(center, r, m));
    const TraceableScene scene(s, 4, 4, "");

    for (int k = 0; k < 50; ++k) {
      const glm::dvec3 dir(square_to_uniform_sphere({u(rng), u(rng)}));
      const glm::dvec3 origin = center + dir * (r * 10.0);
      Ray ray{glm::vec3(origin), glm::vec3(center + random_point(rng, r * 0.5) - origin)};
      Hit hit;
      if (!scene.intersect(ray, &hit)) continue;
      for (int j = 0; j < 10; ++j) {
        const glm::vec3 w = square_to_uniform_sphere({u(rng), u(rng)});
        const float cos_n = glm::dot(w, hit.sp.ng);
        Ray spawned{offset_ray_origin(hit.sp, w), w};
        Hit again;
        const bool found = scene.intersect(spawned, &again);
        if (cos_n > 0) {
          EXPECT_FALSE(found) << "scale " << scale;
          ++outward;
        } else if (cos_n < -1e-3f) {
          // Entering: the next hit is the far side, where the exact (double) solve from the
          // spawned origin puts it, not the near side again.
          ASSERT_TRUE(found) << "scale " << scale;
          double t0, t1;
          ASSERT_TRUE(intersect_sphere(center, r, glm::dvec3(spawned.o), glm::dvec3(w), &t0, &t1));
          const glm::dvec3 exit = glm::dvec3(spawned.o) + t1 * glm::dvec3(w);
          EXPECT_LT(glm::length(glm::dvec3(again.sp.p) - exit), 1e-4 * r + 1e-6 * glm::length(center))
              << "scale " << scale;
          ++inward;
        }
      }
    }
  }
  EXPECT_GT(outward, 10000);
  EXPECT_GT(inward, 10000);
}

INSTANTIATE_TEST_SUITE_P(Scales, Reintersect, ::testing::Values(1e-3, 1.0, 1e4));

}  // namespace
}  // namespace tessera
