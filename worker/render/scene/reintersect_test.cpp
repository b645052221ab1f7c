// Rays spawned off surfaces never hit the surface they leave, at any scene scale (the shape of
// pbrt-v4's Reintersect tests in shapes_test.cpp).
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "render/geometry/sphere_intersector.h"
#include "render/sampling/warp.h"
#include "render/scene/traceable_scene.h"
#include "render/testing/test_scenes.h"

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

/// The crossings of o + t d with the sphere in long double, from the unit direction (the
/// textbook stable form): the reference for intersect_sphere's.
bool reference_crossings(const glm::dvec3& c, double r, const glm::dvec3& o, const glm::dvec3& d,
                         long double* t0, long double* t1) {
  const long double dx = d.x, dy = d.y, dz = d.z;
  const long double len = std::sqrt(dx * dx + dy * dy + dz * dz);
  const long double ux = dx / len, uy = dy / len, uz = dz / len;
  const long double fx = (long double)o.x - c.x, fy = (long double)o.y - c.y, fz = (long double)o.z - c.z;
  const long double b = fx * ux + fy * uy + fz * uz;
  const long double lx = fx - b * ux, ly = fy - b * uy, lz = fz - b * uz;
  const long double disc = (long double)r * r - (lx * lx + ly * ly + lz * lz);
  if (disc < 0) return false;
  const long double s = std::sqrt(disc);
  *t0 = (-b - s) / len;
  *t1 = (-b + s) / len;
  return true;
}

TEST(SphereIntersect, RootsAreAccurateForAnyDirectionLength) {
  // Directions of length 1e-3 to 1e3 (intersect_sphere does not normalise them), from near and
  // far origins (up to 1e4 radii), some grazing the silhouette: each root within a few hundred
  // double ulps of the long-double reference, relative to the distance scale |f| / |d|, plus
  // what the discriminant's own rounding (about eps r^2) moves a root of a grazing ray by.
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int hits = 0, misses = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const double r = std::pow(10.0, -3.0 + 5.0 * u(rng));
    const glm::dvec3 c = random_point(rng, 1e3);
    const glm::dvec3 away(square_to_uniform_sphere({float(u(rng)), float(u(rng))}));
    const glm::dvec3 o = c + away * (r * std::pow(10.0, 0.01 + 4.0 * u(rng)));
    // Toward a point at up to 1.02 radii from the centre, off the line from o to the centre.
    const glm::dvec3 side(square_to_uniform_sphere({float(u(rng)), float(u(rng))}));
    const glm::dvec3 aim = c + glm::normalize(glm::cross(side, away) + 1e-9 * side) * (r * 1.2 * u(rng));
    const glm::dvec3 d = glm::normalize(aim - o) * std::pow(10.0, -3.0 + 6.0 * u(rng));
    double t0 = 0, t1 = 0;
    long double r0 = 0, r1 = 0;
    const bool found = intersect_sphere(c, r, o, d, &t0, &t1);
    const bool expected = reference_crossings(c, r, o, d, &r0, &r1);
    const double scale = (glm::length(o - c) + r) / glm::length(d);
    if (found != expected) {
      // Only a ray that grazes the sphere within rounding may disagree.
      const double chord = found ? t1 - t0 : double(r1 - r0);
      EXPECT_LT(std::abs(chord), 1e-6 * scale) << "trial " << trial;
      continue;
    }
    if (!found) {
      ++misses;
      continue;
    }
    ++hits;
    EXPECT_LE(t0, t1);
    const double len = glm::length(d), half_chord = double(r1 - r0) / 2;
    const double tolerance = 1e-13 * scale + 1e-14 * r * r / (half_chord * len * len);
    EXPECT_NEAR(t0, double(r0), tolerance) << "trial " << trial;
    EXPECT_NEAR(t1, double(r1), tolerance) << "trial " << trial;
  }
  EXPECT_GT(hits, 10000);
  EXPECT_GT(misses, 1000);
}

INSTANTIATE_TEST_SUITE_P(Scales, Reintersect, ::testing::Values(1e-3, 1.0, 1e4));

}  // namespace
}  // namespace tessera
