// Curves through Embree: hits on known tubes (point, normal, uv as Mitsuba defines them), no hit
// from inside a tube, and rays spawned off a tube never hitting it again (the analytic render of
// a tube: geometry/curve_render_test.cpp).
#include "render/geometry/curve.h"

#include <cmath>
#include <random>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "accum/film.h"
#include "render/sampling/warp.h"
#include "render/scene/traceable_scene.h"
#include "render/testing/test_scenes.h"

namespace tessera {
namespace {

/// A scene holding `shape`, with a texture so that hits carry uv and tangents.
Scene scene_with(Shape shape) {
  Scene s;
  shape.material = test::add_diffuse(s, {0.5, 0.5, 0.5});
  Texture checker;
  checker.name = "checker";
  checker.kind = TextureKind::checkerboard;
  s.textures.push_back(checker);
  s.materials[0].reflectance.texture = 0;
  s.shapes.push_back(std::move(shape));
  return s;
}

void expect_near(glm::vec3 a, glm::vec3 b, float tolerance) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

TEST(Curve, LinearTubeHitFromAbove) {
  const TraceableScene scene(
      scene_with(test::curve(CurveBasis::linear, {{-1, 0, 0, 0.5}, {1, 0, 0, 0.5}}, 0)), 4, 4, "");
  ASSERT_TRUE(scene.has_uv());
  Hit hit;
  ASSERT_TRUE(scene.intersect(Ray{{0.3f, 0, 5}, {0, 0, -1}}, &hit));
  expect_near(hit.sp.p, {0.3f, 0, 0.5f}, 1e-5f);
  expect_near(hit.sp.ng, {0, 0, 1}, 1e-5f);
  expect_near(hit.ns, {0, 0, 1}, 1e-5f);
  // Mitsuba's frame for a tangent along +x: v_rot = +z, v_rad = +y; +z is a quarter turn.
  EXPECT_NEAR(hit.uv.x, 0.25f, 1e-5f);
  EXPECT_NEAR(hit.uv.y, 0.65f, 1e-5f);  // (v_local + segment) / segments
  // dp/du = 2 pi axis x (p - c) = 2 pi (1, 0, 0) x (0, 0, 0.5); dp/dv = the segment.
  expect_near(hit.dpdu, {0, -3.14159265f, 0}, 1e-4f);
  expect_near(hit.dpdv, {2, 0, 0}, 1e-4f);
  EXPECT_GE(hit.sp.p_error.z, 0.0f);

  // The rounded end cap: a ray nearly along the axis meets the sphere around the last point
  // (Embree misses rays exactly parallel to a cone's axis, Mitsuba's Embree too).
  ASSERT_TRUE(scene.intersect(Ray{{5, 0, 0}, glm::normalize(glm::vec3(-1, 1e-3f, 0))}, &hit));
  expect_near(hit.sp.p, {1.5f, 0.0035f, 0}, 1e-4f);
  expect_near(hit.sp.ng, {1, 0.007f, 0}, 1e-4f);
}

TEST(Curve, ConeNormalTiltsWithTheRadius) {
  // Radius 0.2 to 0.6 over a length of 1: the side of the cone touching both spheres leans
  // back by asin(0.4) from +z.
  const TraceableScene scene(
      scene_with(test::curve(CurveBasis::linear, {{0, 0, 0, 0.2}, {1, 0, 0, 0.6}}, 0)), 4, 4, "");
  Hit hit;
  ASSERT_TRUE(scene.intersect(Ray{{0.5f, 0, 5}, {0, 0, -1}}, &hit));
  expect_near(hit.sp.ng, {-0.4f, 0, std::sqrt(1 - 0.16f)}, 1e-4f);
}

TEST(Curve, RaysFromInsideATubeLeaveIt) {
  for (CurveBasis basis : {CurveBasis::linear, CurveBasis::bspline}) {
    const TraceableScene scene(
        scene_with(test::curve(basis, {{-3, 0, 0, 1}, {-1, 0, 0, 1}, {1, 0, 0, 1}, {3, 0, 0, 1}}, 0)), 4,
        4, "");
    Hit hit;
    EXPECT_FALSE(scene.intersect(Ray{{0, 0, 0}, {0, 0.6f, 0.8f}}, &hit));
    EXPECT_FALSE(scene.occluded({0, 0, 0}, {0, 0.6f, 0.8f}, 10));
    // From outside the same tube is hit, and blocks.
    EXPECT_TRUE(scene.intersect(Ray{{0, 0, 5}, {0, 0, -1}}, &hit));
    EXPECT_TRUE(scene.occluded({0, 0, 5}, {0, 0, -1}, 10));
  }
}

TEST(Curve, InstancedCurvesArePlacedWithTheirRadii) {
  // A group's tube placed by an instance that scales by 2 and lifts by 1: Embree scales the
  // whole tube, radius included (Mitsuba instances curves the same way).
  Scene s = scene_with(test::curve(CurveBasis::linear, {{-1, 0, 0, 0.5}, {1, 0, 0, 0.5}}, 0));
  ShapeGroup group;
  group.name = "g";
  group.shapes.push_back(s.shapes[0]);
  s.groups.push_back(group);
  Shape instance;
  instance.kind = Shape::Kind::instance;
  instance.group = 0;
  instance.to_world = glm::dmat4(2.0);
  instance.to_world[3] = glm::dvec4(0, 0, 1, 1);
  s.shapes = {instance};
  const TraceableScene scene(s, 4, 4, "");
  Hit hit;
  ASSERT_TRUE(scene.intersect(Ray{{0.6f, 0, 5}, {0, 0, -1}}, &hit));
  expect_near(hit.sp.p, {0.6f, 0, 2}, 1e-4f);
  expect_near(hit.sp.ng, {0, 0, 1}, 1e-4f);
  EXPECT_NEAR(hit.uv.y, 0.65f, 1e-4f);  // x = 0.3 in the group's space
  expect_near(hit.dpdv, {4, 0, 0}, 1e-3f);
  EXPECT_FALSE(scene.intersect(Ray{{0, 0, 1.5f}, {0, 0, 1}}, &hit));  // from inside the tube
}

TEST(Curve, BsplineHitsFollowTheSpline) {
  // Control points on a line: the centre line runs from x = -0.5 to 0.5 (the uniform cubic
  // B-spline's ends are (p0 + 4 p1 + p2) / 6 and (p1 + 4 p2 + p3) / 6), radius 0.25.
  const TraceableScene scene(
      scene_with(test::curve(CurveBasis::bspline,
                       {{-1.5, 0, 0, 0.25}, {-0.5, 0, 0, 0.25}, {0.5, 0, 0, 0.25}, {1.5, 0, 0, 0.25}},
                       0)),
      4, 4, "");
  Hit hit;
  ASSERT_TRUE(scene.intersect(Ray{{0.2f, 5, 0}, {0, -1, 0}}, &hit));
  expect_near(hit.sp.p, {0.2f, 0.25f, 0}, 1e-4f);
  expect_near(hit.sp.ng, {0, 1, 0}, 1e-4f);
  EXPECT_NEAR(hit.uv.x, 0.0f, 1e-4f);  // along v_rad = +y: angle 0
  EXPECT_NEAR(hit.uv.y, 0.7f, 1e-3f);  // the spline is linear in v here: x = v - 0.5
  expect_near(hit.dpdv, {1, 0, 0}, 1e-3f);
  expect_near(glm::normalize(hit.dpdu), {0, 0, 1}, 1e-4f);  // towards v_rot = +z
  EXPECT_NEAR(glm::length(hit.dpdu), 2 * 3.14159265f * 0.25f, 1e-4f);
  // Open ends: past them there is nothing (Mitsuba's bsplinecurve has no end caps).
  EXPECT_FALSE(scene.intersect(Ray{{0.7f, 5, 0}, {0, -1, 0}}, &hit));
}

TEST(Curve, BentBsplineNormalIsPerpendicularToTheSurface) {
  // A quarter arc: the normal from Mitsuba's formula is perpendicular to dp/du and dp/dv.
  const TraceableScene scene(
      scene_with(test::curve(CurveBasis::bspline,
                       {{0, 0, 0, 0.1}, {1, 0, 0, 0.15}, {2, 1, 0, 0.2}, {2, 2, 0, 0.25}, {2, 3, 1, 0.1}},
                       0)),
      4, 4, "");
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  int hits = 0;
  for (int i = 0; i < 500; ++i) {
    const glm::vec3 target(1 + u(rng), 0.5f + 1.5f * u(rng), 0.2f * u(rng));
    const glm::vec3 d = square_to_uniform_sphere({u(rng), u(rng)});
    Hit hit;
    if (!scene.intersect(Ray{target - 10.0f * d, d}, &hit)) continue;
    ++hits;
    EXPECT_LT(glm::dot(hit.sp.ng, d), 0.0f);
    EXPECT_NEAR(glm::dot(hit.sp.ng, glm::normalize(hit.dpdu)), 0.0f, 2e-3f);
    EXPECT_NEAR(glm::dot(hit.sp.ng, glm::normalize(hit.dpdv)), 0.0f, 2e-2f);
    EXPECT_GE(hit.uv.x, 0.0f);
    EXPECT_LT(hit.uv.x, 1.0f);
    EXPECT_GE(hit.uv.y, 0.0f);
    EXPECT_LE(hit.uv.y, 1.0f);
  }
  EXPECT_GT(hits, 100);
}

TEST(Curve, SpawnedRaysDoNotHitTheTubeAgain) {
  // Straight tubes are convex: a ray leaving one, out of it or through it, meets it no more.
  // One segment each (a linear curve of 2 points, a B-spline of 4): where two linear segments
  // meet, Embree reports the joint's hits at the end of a segment (u clamped to 0 or 1), so
  // Mitsuba's normal from the centre line point at u tilts there, and a ray leaving nearly
  // tangentially can meet the next segment (in Mitsuba too).
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  int checked = 0;
  for (double scale : {1e-3, 1.0, 1e3}) {
    for (CurveBasis basis : {CurveBasis::linear, CurveBasis::bspline}) {
      const glm::dvec3 base(37 * scale, -12 * scale, 5 * scale);
      const glm::dvec3 axis = glm::normalize(glm::dvec3(1, 2, -0.5));
      std::vector<glm::dvec4> points;
      const int n = basis == CurveBasis::linear ? 2 : 4;
      for (int k = 0; k < n; ++k) points.emplace_back(base + (k - 0.5 * (n - 1)) * scale * axis, 0.2 * scale);
      const TraceableScene scene(scene_with(test::curve(basis, points, 0)), 4, 4, "");
      for (int r = 0; r < 300; ++r) {
        const glm::dvec3 target = base + (u(rng) - 0.5) * 0.8 * scale * axis;
        const glm::dvec3 d(square_to_uniform_sphere({u(rng), u(rng)}));
        Hit hit;
        if (!scene.intersect(Ray{glm::vec3(target - 5 * scale * d), glm::vec3(d)}, &hit)) continue;
        for (int k = 0; k < 10; ++k) {
          const glm::vec3 w = square_to_uniform_sphere({u(rng), u(rng)});
          Hit again;
          EXPECT_FALSE(scene.intersect(Ray{offset_ray_origin(hit.sp, w), w}, &again))
              << "scale " << scale << " basis " << int(basis) << " ray " << r << " w.n "
              << glm::dot(w, hit.sp.ng);
          ++checked;
        }
      }
    }
  }
  EXPECT_GT(checked, 10000);
}

}  // namespace
}  // namespace tessera
