// Area lights: area, cone and spherical-rectangle sampling seen as directions from a shading
// point (chi-square), pdf() against sample(), irradiance estimates against Lambert's formula,
// which rectangles are found, textured radiance at the sampled point, sides, sphere (u, v).
#include "render/light/area_light.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <optional>

#include "render/light/light_test_support.h"
#include "render/math/ray_offset.h"

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

/// The rectangle corner + [0,1] ex + [0,1] ey as the quad builder makes it (triangles (0,1,2),
/// (0,2,3), front along ex x ey), uvs (0,0), (1,0), (1,1), (0,1).
Geometry emitting_rectangle(glm::vec3 corner, glm::vec3 ex, glm::vec3 ey, float le = 1.0f) {
  Geometry g;
  g.positions = {corner, corner + ex, corner + ex + ey, corner + ey};
  g.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  g.indices = {{0, 1, 2}, {0, 2, 3}};
  for (const glm::u32vec3& t : g.indices) {
    const glm::vec3 p0 = g.positions[t.x], p1 = g.positions[t.y], p2 = g.positions[t.z];
    g.face_normals.push_back(glm::normalize(glm::cross(p1 - p0, p2 - p0)));
    g.point_errors.push_back(triangle_point_error(p0, p1, p2));
  }
  g.emitter = 0;
  g.emission = glm::vec3(le);
  return g;
}

/// Where the ray from ref along d meets the planar light g (a rectangle): the light's pdf of
/// that point, 0 when the ray misses it.
double planar_pdf(const AreaLight& light, const Geometry& g, glm::vec3 ref, glm::vec3 d) {
  const glm::dvec3 c(g.positions[0]), ex = glm::dvec3(g.positions[1]) - c,
      ey = glm::dvec3(g.positions[3]) - c;
  const glm::dvec3 n = glm::normalize(glm::cross(ex, ey));
  const double denom = glm::dot(glm::dvec3(d), n);
  if (denom == 0) return 0;
  const double t = glm::dot(c - glm::dvec3(ref), n) / denom;
  if (!(t > 0)) return 0;
  const glm::dvec3 q = glm::dvec3(ref) + t * glm::dvec3(d) - c;
  const double a = glm::dot(q, ex) / glm::dot(ex, ex), b = glm::dot(q, ey) / glm::dot(ey, ey);
  if (a < 0 || a > 1 || b < 0 || b > 1) return 0;
  return light.pdf(ref, glm::vec3(glm::dvec3(ref) + t * glm::dvec3(d)), glm::vec3(n));
}

/// Bins about the direction from ref to `target`, out to the widest angle of `points`
/// (plus a margin), n_cos x n_phi.
test::DirectionBins bins_towards(glm::vec3 ref, glm::vec3 target,
                                 const std::vector<glm::vec3>& points, int n_cos, int n_phi) {
  const glm::vec3 z = glm::normalize(target - ref);
  const glm::vec3 helper = std::abs(z.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
  const glm::vec3 x = glm::normalize(glm::cross(helper, z));
  test::DirectionBins bins;
  bins.frame = glm::mat3(x, glm::cross(z, x), z);
  double cos_min = 1;
  for (const glm::vec3& p : points) {
    cos_min = std::min(cos_min, double(glm::dot(glm::normalize(p - ref), z)));
  }
  cos_min = std::max(-1.0, cos_min - 0.02 * (1 - cos_min));
  for (int i = 0; i <= n_cos; ++i) bins.cos_edges.push_back(cos_min + (1 - cos_min) * i / n_cos);
  for (int i = 0; i <= n_phi; ++i) bins.phi_edges.push_back(2 * M_PI * i / n_phi);
  return bins;
}

/// The mean and standard error of radiance.y * max(0, cos(n, wi)) / pdf over n samples.
std::pair<double, double> irradiance_estimate(const AreaLight& light, glm::vec3 ref, glm::vec3 n,
                                              int count, uint64_t seed) {
  test::UniformFloats u(seed);
  double sum = 0, sum2 = 0;
  for (int i = 0; i < count; ++i) {
    const LightSample s = light.sample(ref, u.next2());
    if (!(s.pdf > 0)) continue;
    const double f = double(s.radiance.y) * std::max(0.0f, glm::dot(n, s.wi)) / double(s.pdf);
    sum += f;
    sum2 += f * f;
  }
  const double mean = sum / count;
  return {mean, std::sqrt(std::max(0.0, sum2 / count - mean * mean) / count)};
}

TEST(AreaLight, RectanglesAreFoundAndOtherMeshesAreNot) {
  EXPECT_TRUE(
      AreaLight(emitting_rectangle({0, 0, 1}, {2, 0, 0}, {0, 1, 0}), nullptr).is_rectangle());
  // Rotated, and with the triangles' vertices stored apart (no shared indices).
  Geometry rotated = emitting_rectangle({0.3f, -0.2f, 2}, {1, 1, 0.5f}, {-1, 1, 0});
  rotated.positions = {rotated.positions[0], rotated.positions[1], rotated.positions[2],
                       rotated.positions[0], rotated.positions[2], rotated.positions[3]};
  rotated.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 0}, {1, 1}, {0, 1}};
  rotated.indices = {{0, 1, 2}, {3, 4, 5}};
  EXPECT_TRUE(AreaLight(rotated, nullptr).is_rectangle());
  // A parallelogram that is not a rectangle, a trapezoid, three triangles.
  EXPECT_FALSE(
      AreaLight(emitting_rectangle({0, 0, 1}, {2, 0, 0}, {0.5f, 1, 0}), nullptr).is_rectangle());
  Geometry trapezoid = emitting_rectangle({0, 0, 1}, {2, 0, 0}, {0, 1, 0});
  trapezoid.positions[2].x = 1.5f;
  EXPECT_FALSE(AreaLight(trapezoid, nullptr).is_rectangle());
  Geometry mesh = emitting_mesh();
  mesh.emission_texture = -1;
  EXPECT_FALSE(AreaLight(mesh, nullptr).is_rectangle());
}

TEST(AreaLight, RectangleSamplesMatchPdfChiSquare) {
  // A rotated rectangle, seen from about its diagonal away (the farthest it is sampled by
  // solid angle), from nearby (about 1.5 sr), from close (about 5 sr, most directions grazing
  // the light) and from a hair off its plane (nearly 2 pi).
  const glm::vec3 corner(-0.5f, -0.3f, 1.0f), ex(1.2f, 0.3f, 0.1f), ey(-0.3f, 0.9f, 0.9f);
  const glm::vec3 ey_orthogonal = ey - ex * (glm::dot(ex, ey) / glm::dot(ex, ex));
  const Geometry g = emitting_rectangle(corner, ey_orthogonal, ex);  // front towards the refs
  const AreaLight light(g, nullptr);
  ASSERT_TRUE(light.is_rectangle());
  const glm::vec3 center = corner + 0.5f * (ex + ey_orthogonal);
  const glm::vec3 n = glm::normalize(glm::cross(ey_orthogonal, ex));
  uint64_t seed = 30;
  for (const float distance : {1.6f, 0.8f, 0.05f, 1e-4f}) {
    // Off-centre, except a hair off the plane, where bins about a grazing axis would cut the
    // light's silhouette too finely for the test's integration.
    const glm::vec3 ref = center + n * distance + (distance > 0.01f ? 0.2f : 0.0f) * ex;
    ASSERT_TRUE(light.solid_angle_sampled(ref)) << distance;
    test::UniformFloats u(seed++);
    const auto sample = [&]() -> std::optional<glm::vec3> {
      const LightSample s = light.sample(ref, u.next2());
      if (!(s.pdf > 0)) return std::nullopt;
      return s.wi;
    };
    const auto pdf = [&](glm::vec3 d) { return planar_pdf(light, g, ref, d); };
    const test::DirectionBins bins = bins_towards(ref, center, g.positions, 12, 16);
    const test::DirectionChiSquareResult r = test::chi_square_directions(bins, 100000, sample, pdf);
    EXPECT_GT(r.p_value, test::kChiSquareLevel) << "distance " << distance << ": " << r.detail;
  }
}

TEST(AreaLight, RectangleByAreaSamplesMatchPdfChiSquare) {
  // Where a rectangle is sampled by area (farther than its diagonal from its centre, or a hair
  // off its plane beside it), its point is corner + u.x ex + u.y ey, not a triangle picked
  // first: the directions must still follow pdf() = d^2 / (|cos| area).
  const glm::vec3 corner(-0.5f, -0.3f, 1.0f), ex(1.2f, 0.3f, 0.1f), ey(-0.3f, 0.9f, 0.9f);
  const glm::vec3 ey_orthogonal = ey - ex * (glm::dot(ex, ey) / glm::dot(ex, ex));
  const Geometry g = emitting_rectangle(corner, ey_orthogonal, ex);
  const AreaLight light(g, nullptr);
  ASSERT_TRUE(light.is_rectangle());
  const glm::vec3 center = corner + 0.5f * (ex + ey_orthogonal);
  const glm::vec3 n = glm::normalize(glm::cross(ey_orthogonal, ex));
  const float diagonal = glm::length(ex + ey_orthogonal);
  uint64_t seed = 40;
  // Off-centre at 1.2 diagonals, and obliquely at 1.5 diagonals (grazing the light at about
  // 70 degrees).
  for (const glm::vec3 ref : {center + 1.2f * diagonal * n + 0.3f * ex,
                              center + 0.5f * diagonal * n + 1.4f * diagonal * glm::normalize(ex)}) {
    ASSERT_FALSE(light.solid_angle_sampled(ref));
    ASSERT_FALSE(light.behind(ref));
    test::UniformFloats u(seed++);
    const auto sample = [&]() -> std::optional<glm::vec3> {
      const LightSample s = light.sample(ref, u.next2());
      if (!(s.pdf > 0)) return std::nullopt;
      return s.wi;
    };
    const auto pdf = [&](glm::vec3 d) { return planar_pdf(light, g, ref, d); };
    const test::DirectionBins bins = bins_towards(ref, center, g.positions, 12, 16);
    const test::DirectionChiSquareResult r = test::chi_square_directions(bins, 100000, sample, pdf);
    EXPECT_GT(r.p_value, test::kChiSquareLevel) << "ref " << ref.x << " " << ref.y << " " << ref.z << ": " << r.detail;
  }
}

TEST(AreaLight, RectanglePdfAgreesWithSampleBitForBit) {
  Geometry g = emitting_rectangle({-1, -1, 1}, {0, 2, 0}, {2, 0, 0});  // faces -z
  g.emission_texture = 0;
  const AreaLight light(g, [](int32_t, glm::vec2 uv) { return glm::vec3(uv.x, uv.y, 1.0f); });
  test::UniformFloats u(31);
  for (const glm::vec3 ref : {glm::vec3(0.3f, 0.2f, -0.5f), glm::vec3(3.0f, 0.0f, 0.9f),
                              glm::vec3(0.0f, 0.0f, 0.99999f)}) {
    for (int i = 0; i < 200; ++i) {
      const LightSample s = light.sample(ref, u.next2());
      if (!(s.pdf > 0)) continue;
      EXPECT_EQ(light.pdf(ref, s.point.p, s.point.ng), s.pdf);
      EXPECT_NEAR(s.point.p.z, 1.0f, 1e-6f);
      // uv (0, 0) at the corner (-1, -1), (1, 0) at (-1, 1), (0, 1) at (1, -1).
      EXPECT_NEAR(s.radiance.x, (s.point.p.y + 1) / 2, 1e-5f);
      EXPECT_NEAR(s.radiance.y, (s.point.p.x + 1) / 2, 1e-5f);
      EXPECT_EQ(s.point.ng, glm::vec3(0, 0, -1));
      EXPECT_NEAR(glm::length(s.point.p - ref), s.distance, 1e-5f);
    }
  }
  // Farther than its diagonal (2.83): by area; in the plane: by area (no solid angle there).
  EXPECT_FALSE(light.solid_angle_sampled({0, 0, -40}));
  EXPECT_FALSE(light.solid_angle_sampled({0, 0, -1.9f}));
  EXPECT_FALSE(light.solid_angle_sampled({1, 0, 1}));
  EXPECT_TRUE(light.solid_angle_sampled({0, 0, -1.5f}));
}

TEST(AreaLight, NothingIsDrawnBehindAOneSidedRectangleAndNothingIsLostThere) {
  // behind() only where no point of the light emits towards ref: at points around the light
  // (near its plane on both sides, far off, and far from the origin), whenever behind(ref),
  // no area sample sends radiance to ref; and points clearly behind are behind().
  test::UniformFloats u(33);
  // Edges and offsets of few bits, so that the vertices far from the origin are exact.
  for (const glm::vec3 offset : {glm::vec3(0.0f), glm::vec3(1024, -512, 2048)}) {
    const glm::vec3 corner = offset + glm::vec3(-0.5f, -0.25f, 1.0f);
    const glm::vec3 ex(0.25f, 1.125f, 0.125f), ey(1.125f, -0.25f, 0.0f);
    const Geometry g = emitting_rectangle(corner, ex, ey);
    const AreaLight light(g, nullptr);
    ASSERT_TRUE(light.is_rectangle());
    const glm::vec3 center = corner + 0.5f * (ex + ey);
    const glm::vec3 n = g.face_normals[0];
    int behind = 0;
    for (int k = 0; k < 4000; ++k) {
      // Distances to the plane from 1e-6 to 10 on either side, spread along it up to 50.
      const float side = k % 2 ? 1.0f : -1.0f;
      const float height = side * std::pow(10.0f, -6.0f + 7.0f * u.next());
      const float spread = std::pow(10.0f, -2.0f + 3.7f * u.next());
      const glm::vec3 ref = center + height * n +
                            spread * glm::vec3(u.next() - 0.5f, u.next() - 0.5f, u.next() - 0.5f);
      if (!light.behind(ref)) continue;
      ++behind;
      EXPECT_EQ(light.sample(ref, u.next2()).pdf, 0.0f);
      EXPECT_EQ(light.pdf(ref, center, n), 0.0f);
      for (int i = 0; i < 50; ++i) {
        const AreaLight::PointSample ps = light.sample_point(u.next2());
        ASSERT_EQ(light.emitted(ps.uv, ps.sp.ng, ref - ps.sp.p), glm::vec3(0.0f))
            << "height " << height << " spread " << spread;
      }
    }
    EXPECT_GT(behind, 1000);
    EXPECT_TRUE(light.behind(center - 0.01f * n));
    EXPECT_FALSE(light.behind(center + 0.01f * n));
  }
  // Two-sided emission: never behind.
  Geometry two = emitting_rectangle({-1, -1, 1}, {0, 2, 0}, {2, 0, 0});
  two.two_sided_emission = true;
  EXPECT_FALSE(AreaLight(two, nullptr).behind({0, 0, 5}));
  EXPECT_FALSE(AreaLight(two, nullptr).behind({0, 0, -5}));
}

TEST(AreaLight, RectangleEstimatesLambertsIrradiance) {
  // The estimator's mean is the irradiance (every case sees the whole light above its
  // horizon: Lambert's formula counts the part below it negative), by solid angle (down to a
  // hair off the plane, where the light fills nearly the hemisphere) and in the fall-backs to
  // area sampling (far off; close to the plane beside the light).
  const Geometry g = emitting_rectangle({-1, -0.5f, 1}, {0, 1, 0}, {2, 0, 0}, 3.0f);  // faces -z
  const AreaLight light(g, nullptr);
  struct Case {
    glm::vec3 ref, n;
  };
  const Case cases[] = {{{0.2f, 0.1f, 0.0f}, {0, 0, 1}},
                        {{1.5f, 0.4f, 0.7f}, glm::normalize(glm::vec3(-1, 0.2f, 0.5f))},
                        {{0.3f, 0.0f, 0.99995f}, {0, 0, 1}},
                        {{0.5f, 0.3f, -25.0f}, {0, 0, 1}},
                        {{3.0f, 0.0f, 0.99999f}, glm::normalize(glm::vec3(-1, 0, 0.2f))}};
  EXPECT_TRUE(light.solid_angle_sampled(cases[2].ref));
  EXPECT_FALSE(light.solid_angle_sampled(cases[3].ref));
  EXPECT_FALSE(light.solid_angle_sampled(cases[4].ref));
  uint64_t seed = 40;
  for (const Case& c : cases) {
    const double expected =
        test::polygon_irradiance(g.positions, glm::dvec3(c.ref), glm::dvec3(c.n), 3.0);
    const auto [mean, se] = irradiance_estimate(light, c.ref, c.n, 40000, seed++);
    EXPECT_NEAR(mean, expected, 5 * se + 1e-4 * expected) << c.ref.x << " " << c.ref.z;
  }
}

TEST(AreaLight, SphereConeEstimatesIrradianceAndAgreesWithPdf) {
  // A sphere of radiance 2 seen from outside subtends a cap: irradiance on a surface facing
  // its centre is pi L sin^2(theta_max); from inside, sampling by area still sees nothing of
  // a one-sided sphere.
  const Geometry g = emitting_sphere({0, 0, 3}, 1.5);
  const AreaLight light(g, nullptr);
  uint64_t seed = 50;
  for (const float z : {0.0f, -100.0f, 1.4f}) {
    const glm::vec3 ref(0, 0, z);
    ASSERT_TRUE(light.solid_angle_sampled(ref));
    const double d = 3.0 - z, sin2 = 1.5 * 1.5 / (d * d);
    const auto [mean, se] = irradiance_estimate(light, ref, {0, 0, 1}, 20000, seed++);
    EXPECT_NEAR(mean, M_PI * sin2, 5 * se + 1e-5 * M_PI * sin2) << z;
    test::UniformFloats u(seed++);
    for (int i = 0; i < 100; ++i) {
      const LightSample s = light.sample(ref, u.next2());
      ASSERT_GT(s.pdf, 0);
      EXPECT_EQ(light.pdf(ref, s.point.p, s.point.ng), s.pdf);
      EXPECT_NEAR(glm::length(s.point.p - glm::vec3(g.center)), 1.5f, 1e-5f);
      EXPECT_GT(glm::dot(s.point.ng, -s.wi), 0.0f);  // the near side
    }
  }
  EXPECT_FALSE(light.solid_angle_sampled({0, 0, 3.5f}));
  EXPECT_FALSE(light.solid_angle_sampled({0, 0, 1.5f}));  // on the sphere
  EXPECT_FALSE(light.solid_angle_sampled({0, 0, 1.4999f}));  // a hair outside
  EXPECT_EQ(irradiance_estimate(light, {0, 0, 3.5f}, {0, 0, 1}, 100, 59).first, 0.0);
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
  const test::DirectionChiSquareResult r = test::chi_square_directions(bins, 100000, sample, pdf);
  EXPECT_GT(r.p_value, test::kChiSquareLevel) << r.detail;
}

TEST(AreaLight, SphereSamplesMatchPdfChiSquare) {
  // Seen from outside: uniform in the cone the sphere subtends.
  const Geometry g = emitting_sphere({0, 0, 3}, 1.5);
  const AreaLight light(g, nullptr);
  const glm::vec3 ref(0.1f, 0.0f, 0.0f);
  test::UniformFloats u(12);
  // Bins about the axis towards the centre, up to the silhouette cone, shrinking geometrically
  // towards it (as for a density growing there, which area sampling had).
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
  const test::DirectionChiSquareResult r = test::chi_square_directions(bins, 100000, sample, pdf);
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
