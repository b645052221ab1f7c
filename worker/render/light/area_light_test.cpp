// Area lights: uniform area sampling seen as directions from a shading point (chi-square),
// pdf() against sample(), textured radiance at the sampled point, sides, sphere (u, v).
#include "render/light/area_light.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <optional>

#include "render/light/light_test_support.h"
#include "render/ray_offset.h"

namespace tessera {
namespace {

/// Triangles facing -z in the plane z = 1 over [-1, 1] x [-1, 0.5], in three triangles of
/// unequal area, with uvs = (x, y).
Geometry emitting_mesh() {
  Geometry g;
  g.positions = {{-1, -1, 1}, {1, -1, 1}, {1, 0.5f, 1}, {-1, 0.5f, 1}, {0, 0.5f, 1}};
  g.indices = {{0, 2, 1}, {0, 4, 2}, {0, 3, 4}};
  for (const glm::vec3& p : g.positions) g.uvs.emplace_back(p.x, p.y);
  for (const glm::u32vec3& t : g.indices) {
    const glm::vec3 p0 = g.positions[t.x], p1 = g.positions[t.y], p2 = g.positions[t.z];
    g.face_normals.push_back(glm::normalize(glm::cross(p1 - p0, p2 - p0)));
    g.point_errors.push_back(triangle_point_error(p0, p1, p2));
  }
  g.emitter = 0;
  g.emission = {2, 2, 2};
  g.emission_texture = 3;
  return g;
}

/// A texture that is positive everywhere and varies with (u, v).
glm::vec3 gradient(int32_t texture, glm::vec2 uv) {
  EXPECT_EQ(texture, 3);
  return {1.0f + uv.x, 1.5f + uv.y, 1.0f};
}

Geometry emitting_sphere(glm::dvec3 center, double radius) {
  Geometry g;
  g.kind = Geometry::Kind::sphere;
  g.center = center;
  g.radius = radius;
  g.emitter = 0;
  g.emission = {1, 1, 1};
  return g;
}

TEST(AreaLight, TriangleSamplesMatchPdfChiSquare) {
  const Geometry g = emitting_mesh();
  const AreaLight light(g, gradient);
  const glm::vec3 ref(0.2f, -0.1f, 0.0f);
  test::UniformFloats u(11);
  // Every direction to the light has cos(theta) about +z above 0.4.
  test::DirectionBins bins;
  for (int i = 0; i <= 12; ++i) bins.cos_edges.push_back(0.4 + 0.6 * i / 12.0);
  for (int i = 0; i <= 16; ++i) bins.phi_edges.push_back(2 * M_PI * i / 16.0);
  const auto sample = [&]() -> std::optional<glm::vec3> {
    const LightSample s = light.sample(ref, u.next2());
    if (!(s.pdf > 0)) return std::nullopt;
    return s.wi;
  };
  const auto pdf = [&](glm::vec3 d) -> double {
    // Where the ray from ref along d meets the plane z = 1, if on the light.
    if (!(d.z > 0)) return 0;
    const glm::vec3 p = ref + d * ((1.0f - ref.z) / d.z);
    if (p.x < -1 || p.x > 1 || p.y < -1 || p.y > 0.5f) return 0;
    return light.pdf(ref, p, {0, 0, -1});
  };
  const test::ChiSquareResult r = test::chi_square_directions(bins, 100000, sample, pdf);
  EXPECT_GT(r.p_value, test::kChiSquareLevel) << r.detail;
}

TEST(AreaLight, SphereSamplesMatchPdfChiSquare) {
  // Uniform by area over the whole sphere; the far side faces away and gives nothing, so the
  // directions that come back are distributed as the near side's density.
  const Geometry g = emitting_sphere({0, 0, 3}, 1.5);
  const AreaLight light(g, nullptr);
  const glm::vec3 ref(0.1f, 0.0f, 0.0f);
  test::UniformFloats u(12);
  // Bins about the axis towards the centre, up to the silhouette cone. The density grows
  // without bound towards the silhouette (grazing points), so the bins shrink geometrically
  // towards it to keep every bin's integral accurate.
  const glm::dvec3 axis = glm::normalize(g.center - glm::dvec3(ref));
  const double distance = glm::length(g.center - glm::dvec3(ref));
  const double cos_max = std::sqrt(1 - (g.radius / distance) * (g.radius / distance));
  test::DirectionBins bins;
  const glm::vec3 z(axis), x = glm::normalize(glm::cross(glm::vec3(0, 1, 0), z));
  bins.frame = glm::mat3(x, glm::cross(z, x), z);
  bins.cos_edges.push_back(cos_max);
  for (int k = 14; k >= 0; --k)
    bins.cos_edges.push_back(cos_max + (1 - cos_max) * std::ldexp(1.0, -k));
  for (int i = 0; i <= 12; ++i) bins.phi_edges.push_back(2 * M_PI * i / 12.0);
  const auto sample = [&]() -> std::optional<glm::vec3> {
    const LightSample s = light.sample(ref, u.next2());
    if (!(s.pdf > 0)) return std::nullopt;
    return s.wi;
  };
  const auto pdf = [&](glm::vec3 d) -> double {
    const glm::dvec3 oc = glm::dvec3(ref) - g.center;
    const double b = glm::dot(oc, glm::dvec3(d)), c = glm::dot(oc, oc) - g.radius * g.radius;
    const double disc = b * b - c;
    if (disc <= 0) return 0;
    const glm::vec3 p = glm::vec3(glm::dvec3(ref) + glm::dvec3(d) * (-b - std::sqrt(disc)));
    return light.pdf(ref, p, glm::normalize(p - glm::vec3(g.center)));
  };
  const test::ChiSquareResult r = test::chi_square_directions(bins, 100000, sample, pdf);
  EXPECT_GT(r.p_value, test::kChiSquareLevel) << r.detail;
}

TEST(AreaLight, PdfAgreesWithSampleAndRadianceFollowsTheTexture) {
  const Geometry g = emitting_mesh();
  const AreaLight light(g, gradient);
  const glm::vec3 ref(0.3f, 0.2f, -0.5f);
  test::UniformFloats u(4);
  for (int i = 0; i < 1000; ++i) {
    const LightSample s = light.sample(ref, u.next2());
    ASSERT_GT(s.pdf, 0);
    EXPECT_FALSE(s.delta);
    EXPECT_NEAR(glm::length(s.point.p - ref), s.distance, 1e-5f);
    EXPECT_NEAR(light.pdf(ref, s.point.p, s.point.ng), s.pdf, 1e-4f * s.pdf);
    // uvs are (x, y): the radiance is emission * gradient at the sampled point.
    EXPECT_NEAR(s.radiance.x, 2 * (1 + s.point.p.x), 1e-5f);
    EXPECT_NEAR(s.radiance.y, 2 * (1.5f + s.point.p.y), 1e-5f);
    EXPECT_EQ(s.point.ng, glm::vec3(0, 0, -1));
  }
  EXPECT_NEAR(light.area(), 3.0f, 1e-6f);
}

TEST(AreaLight, OneSidedEmitsFromTheFrontOnly) {
  Geometry g = emitting_mesh();
  g.emission_texture = -1;
  const AreaLight one(g, nullptr);
  EXPECT_EQ(one.emitted({0, 0}, {0, 0, -1}, {0, 0, -1}), glm::vec3(2));
  EXPECT_EQ(one.emitted({0, 0}, {0, 0, -1}, {0, 0, 1}), glm::vec3(0));
  test::UniformFloats u(5);
  EXPECT_EQ(one.sample({0, 0, 2}, u.next2()).pdf, 0.0f);  // behind the light
  Geometry g2 = g;
  g2.two_sided_emission = true;
  const AreaLight two(g2, nullptr);
  EXPECT_EQ(two.emitted({0, 0}, {0, 0, -1}, {0, 0, 1}), glm::vec3(2));
  EXPECT_GT(two.sample({0, 0, 2}, u.next2()).pdf, 0.0f);
  EXPECT_NEAR(two.power(), 2 * one.power(), 1e-9 * one.power());
  EXPECT_NEAR(one.power(), M_PI * 3 * 2, 1e-4);
}

/// |a - b| for u coordinates, which wrap around at 1.
float wrapped_distance(float a, float b) {
  const float d = std::abs(a - b);
  return std::min(d, 1.0f - d);
}

TEST(AreaLight, SphereUvIsMitsubasParametrisation) {
  const glm::mat3 id(1.0f);
  EXPECT_NEAR(sphere_uv(id, {1, 0, 0}).x, 0.0f, 1e-6f);
  EXPECT_NEAR(sphere_uv(id, {1, 0, 0}).y, 0.5f, 1e-6f);
  EXPECT_NEAR(sphere_uv(id, {0, 1, 0}).x, 0.25f, 1e-6f);
  EXPECT_NEAR(sphere_uv(id, {0, -1, 0}).x, 0.75f, 1e-6f);
  EXPECT_NEAR(sphere_uv(id, {0, 0, 1}).y, 0.0f, 1e-6f);
  EXPECT_NEAR(sphere_uv(id, {0, 0, -1}).y, 1.0f, 1e-6f);
  // A frame rotated 90 degrees about z: its +x is the world's +y.
  const glm::mat3 frame(glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(0, 0, 1)));
  EXPECT_NEAR(wrapped_distance(sphere_uv(frame, {0, 1, 0}).x, 0.0f), 0.0f, 1e-6f);
  EXPECT_NEAR(sphere_uv(frame, {-1, 0, 0}).x, 0.25f, 1e-6f);
}

TEST(AreaLight, SphereSamplesCarryTheirUv) {
  Geometry g = emitting_sphere({1, 2, 3}, 2.0);
  g.frame = glm::mat3(glm::rotate(glm::mat4(1.0f), glm::radians(40.0f), glm::vec3(1, 1, 0)));
  g.emission_texture = 0;
  const AreaLight light(g, [](int32_t, glm::vec2 uv) { return glm::vec3(uv.x, uv.y, 1.0f); });
  test::UniformFloats u(6);
  for (int i = 0; i < 200; ++i) {
    const AreaLight::PointSample ps = light.sample_point(u.next2());
    const glm::vec3 dir = glm::normalize(ps.sp.p - glm::vec3(g.center));
    const glm::vec2 expected = sphere_uv(g.frame, dir);
    EXPECT_NEAR(wrapped_distance(ps.uv.x, expected.x), 0.0f, 1e-4f);
    EXPECT_NEAR(ps.uv.y, expected.y, 1e-4f);
    EXPECT_NEAR(glm::length(ps.sp.p - glm::vec3(g.center)), 2.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(ps.sp.ng, dir), 1.0f, 1e-5f);
  }
}

}  // namespace
}  // namespace tessera
