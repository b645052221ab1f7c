// The light set: picking by importance at the point (nearer lights more often, none that
// cannot reach the point, every one that can), the pick probability in every pdf, pdf_area and
// pdf_environment against sample(), the environment mixture (chi-square), spot and projector
// lights beside an environment, bad lights.
#include "render/light/light_set.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "render/light/light_test_support.h"
#include "render/sampling/warp.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

const TextureLookup kNoTextures = [](int32_t, glm::vec2) { return glm::vec3(1.0f); };

Light light_of(LightKind kind, glm::dvec3 value, glm::dmat4 to_world = glm::dmat4(1.0)) {
  Light l;
  l.kind = kind;
  l.origin = "lights[" + std::to_string(int(kind)) + "]";
  l.value = value;
  l.to_world = to_world;
  return l;
}

/// A one-sided quad facing -z over [-1, 1]^2 at z = 1.
Geometry ceiling_quad(int32_t index, float le) {
  Geometry g;
  g.positions = {{-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}};
  g.indices = {{0, 2, 1}, {0, 3, 2}};
  for (const glm::u32vec3& t : g.indices) {
    const glm::vec3 p0 = g.positions[t.x], p1 = g.positions[t.y], p2 = g.positions[t.z];
    g.face_normals.push_back(glm::normalize(glm::cross(p1 - p0, p2 - p0)));
    g.point_errors.push_back(triangle_point_error(p0, p1, p2));
  }
  g.emitter = index;
  g.emission = glm::vec3(le);
  return g;
}

Geometry sphere_light(int32_t index, glm::dvec3 center, double radius, float le) {
  Geometry g;
  g.kind = Geometry::Kind::sphere;
  g.center = center;
  g.radius = radius;
  g.emitter = index;
  g.emission = glm::vec3(le);
  return g;
}

/// An 8 x 5 map with variation and one bright texel, as an EXR file "sky.exr".
FileReader sky_reader() {
  std::vector<float> rgb;
  for (int y = 0; y < 5; ++y) {
    for (int x = 0; x < 8; ++x) {
      const float v = (x == 5 && y == 2) ? 200.0f : 0.2f + 0.1f * float((x + 2 * y) % 4);
      rgb.insert(rgb.end(), {v, v, 0.5f * v});
    }
  }
  return test::reader_of("sky.exr", test::exr_bytes(8, 5, rgb));
}

Light sky() {
  Light l = light_of(LightKind::envmap, {1, 1, 1});
  l.file = "sky.exr";
  return l;
}

const SurfacePoint kRef{{0.1f, -0.2f, 0.0f}, {0, 0, 0}, {0, 0, 1}};

TEST(LightSet, WithoutLightsSamplesNothing) {
  const LightSet set({}, {}, test::reader_of("x", ""), kNoTextures, 1.0f);
  EXPECT_TRUE(set.empty());
  EXPECT_EQ(set.sample(kRef, 0.5f, {0.5f, 0.5f}).pdf, 0.0f);
  EXPECT_EQ(set.environment({0, 0, 1}), glm::vec3(0.0f));
  EXPECT_EQ(set.pdf_environment(kRef, {0, 0, 1}), 0.0f);
}

TEST(LightSet, PicksAsOftenAsThePickProbabilityItReports) {
  // Two delta lights: a sample's pdf is its pick probability alone, and the picks must come
  // in those proportions, the two summing to 1.
  const LightSet set(
      {},
      {light_of(LightKind::point, {1, 1, 1}, glm::translate(glm::dmat4(1.0), {0, 0, 2})),
       light_of(LightKind::directional, {1, 1, 1})},
      test::reader_of("x", ""), kNoTextures, 1.0f);
  test::UniformFloats u(21);
  const int n = 20000;
  int points = 0;
  float point_pmf = 0, directional_pmf = 0;
  for (int i = 0; i < n; ++i) {
    const LightSample s = set.sample(kRef, u.next(), u.next2());
    ASSERT_TRUE(s.delta);
    if (std::isfinite(s.distance)) {
      ++points;
      point_pmf = s.pdf;
    } else {
      directional_pmf = s.pdf;
    }
  }
  EXPECT_NEAR(point_pmf + directional_pmf, 1.0f, 1e-6f);
  EXPECT_GT(point_pmf, 0.05f);
  EXPECT_GT(directional_pmf, 0.05f);
  const double se = std::sqrt(n * double(point_pmf) * double(directional_pmf));
  EXPECT_NEAR(points, double(point_pmf) * n, 5 * se);
}

/// Two equal ceiling quads (emitters 0 and 1) facing -z at z = 1, centred at x = -3 and x = 3.
struct TwoQuads {
  Geometry left = ceiling_quad(0, 3.0f), right = ceiling_quad(1, 3.0f);
  TwoQuads() {
    for (glm::vec3& p : left.positions) p.x -= 3;
    for (glm::vec3& p : right.positions) p.x += 3;
  }
};

TEST(LightSet, PicksTheLightNearerThePointMoreOften) {
  const TwoQuads quads;
  const LightSet set({&quads.left, &quads.right}, {}, test::reader_of("x", ""), kNoTextures, 5.0f);
  // Below the right quad: it gets nearly every pick; between them, half each.
  const SurfacePoint below_right{{3.0f, 0.0f, 0.0f}, {0, 0, 0}, {0, 0, 1}};
  const SurfacePoint between{{0.0f, 0.0f, 0.0f}, {0, 0, 0}, {0, 0, 1}};
  const glm::vec3 hit_left(-3, 0, 1), hit_right(3, 0, 1), down(0, 0, -1);
  const float pick_left = set.pdf_area(quads.left, 0, below_right, hit_left, down) /
                          AreaLight(quads.left, nullptr).pdf(below_right.p, hit_left, down);
  const float pick_right = set.pdf_area(quads.right, 0, below_right, hit_right, down) /
                           AreaLight(quads.right, nullptr).pdf(below_right.p, hit_right, down);
  EXPECT_NEAR(pick_left + pick_right, 1.0f, 1e-5f);
  EXPECT_GT(pick_right, 0.9f);
  EXPECT_GT(pick_left, 0.0f);
  const float half_left = set.pdf_area(quads.left, 0, between, hit_left, down) /
                          AreaLight(quads.left, nullptr).pdf(between.p, hit_left, down);
  EXPECT_NEAR(half_left, 0.5f, 1e-4f);
  // Above the quads (behind their one-sided backs, beyond the slack of their bounding
  // spheres), neither can give anything: no picks.
  const SurfacePoint above{{3.0f, 0.0f, 4.0f}, {0, 0, 0}, {0, 0, 1}};
  EXPECT_EQ(set.pdf_area(quads.right, 0, above, hit_right, down), 0.0f);
  test::UniformFloats u(26);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(set.sample(above, u.next(), u.next2()).pdf, 0.0f);
}

TEST(LightSet, EveryLightThatCanReachAPointKeepsAPickProbability) {
  // Lights of every kind and orientation; at points on a grid, with normals in many
  // directions, every area light that has a point facing the reference point (its front,
  // seen at a positive cosine) must have a positive pick probability there, as the point
  // and environment lights must everywhere.
  std::vector<Geometry> shapes;
  shapes.push_back(ceiling_quad(0, 3.0f));
  Geometry wall = ceiling_quad(1, 0.5f);  // facing +x at x = -2
  for (glm::vec3& p : wall.positions) p = {-2.0f, p.y, p.x * 0.5f};
  wall.face_normals.clear();
  for (const glm::u32vec3& t : wall.indices) {
    const glm::vec3 p0 = wall.positions[t.x], p1 = wall.positions[t.y], p2 = wall.positions[t.z];
    wall.face_normals.push_back(glm::normalize(glm::cross(p1 - p0, p2 - p0)));
  }
  shapes.push_back(wall);
  Geometry two_sided = ceiling_quad(2, 0.01f);  // tiny and dim, far off, two-sided
  for (glm::vec3& p : two_sided.positions) p = p * 0.01f + glm::vec3(6, 6, -3);
  two_sided.two_sided_emission = true;
  shapes.push_back(two_sided);
  shapes.push_back(sphere_light(3, {1.5, -1.5, 0.2}, 0.3, 50.0f));
  std::vector<const Geometry*> pointers;
  for (const Geometry& g : shapes) pointers.push_back(&g);
  const LightSet set(
      pointers,
      {light_of(LightKind::point, {100, 100, 100}, glm::translate(glm::dmat4(1.0), {0, 0.5, 0.5})),
       light_of(LightKind::constant, {0.01, 0.01, 0.01})},
      test::reader_of("x", ""), kNoTextures, 8.0f);
  std::vector<AreaLight> lights;
  for (const Geometry& g : shapes) lights.emplace_back(g, nullptr);
  test::UniformFloats u(27);
  int checked = 0;
  for (int i = 0; i < 300; ++i) {
    const glm::vec3 p(-3 + 6 * u.next(), -3 + 6 * u.next(), -3 + 5 * u.next());
    glm::vec3 n(u.next() - 0.5f, u.next() - 0.5f, u.next() - 0.5f);
    if (i % 10 == 0) n = glm::vec3(1, 0, 0);  // some normals exactly along an axis
    n = glm::normalize(n);
    const SurfacePoint ref{p, {0, 0, 0}, n};
    EXPECT_GT(set.pdf_environment(ref, {0, 0, 1}), 0.0f) << i;
    for (size_t k = 0; k < lights.size(); ++k) {
      // A point of the light facing p, if any, among 64 spread over it.
      for (int j = 0; j < 64; ++j) {
        const AreaLight::PointSample ps =
            lights[k].sample_point({(j % 8 + 0.5f) / 8, (j / 8 + 0.5f) / 8});
        const glm::vec3 to_p = p - ps.sp.p;
        const bool faces = shapes[k].two_sided_emission || glm::dot(ps.sp.ng, to_p) > 0;
        if (!faces || glm::dot(to_p, to_p) == 0) continue;
        ++checked;
        EXPECT_GT(set.pdf_area(shapes[k], 0, ref, ps.sp.p, ps.sp.ng), 0.0f)
            << "light " << k << " at point " << i;
        break;
      }
    }
  }
  EXPECT_GT(checked, 600);
}

TEST(LightSet, AreaAndEnvironmentPdfsAgreeWithSample) {
  const Geometry quad = ceiling_quad(0, 3.0f);
  const Geometry ball = sphere_light(1, {3, 0, 0.5}, 0.5, 5.0f);
  const LightSet set({&quad, &ball}, {light_of(LightKind::constant, {0.1, 0.1, 0.1}), sky()},
                     sky_reader(), kNoTextures, 0.5f);
  test::UniformFloats u(22);
  int area = 0, environment = 0;
  for (int i = 0; i < 4000; ++i) {
    const LightSample s = set.sample(kRef, u.next(), u.next2());
    if (!(s.pdf > 0)) continue;
    ASSERT_FALSE(s.delta);
    ASSERT_TRUE(std::isfinite(s.pdf));
    if (std::isinf(s.distance)) {
      ++environment;
      EXPECT_NEAR(set.pdf_environment(kRef, s.wi), s.pdf, 1e-4f * s.pdf);
      // The pick's sum gives the same bits as evaluating every light again.
      ASSERT_GE(s.pick_sum, 0.0f);
      EXPECT_EQ(set.pdf_environment(kRef, s.wi, s.pick_sum), set.pdf_environment(kRef, s.wi));
      EXPECT_EQ(set.environment(s.wi), s.radiance);
      continue;
    }
    ++area;
    const bool on_ball = std::abs(glm::length(s.point.p - glm::vec3(ball.center)) - 0.5f) < 1e-4f;
    const Geometry& g = on_ball ? ball : quad;
    EXPECT_NEAR(set.pdf_area(g, 0, kRef, s.point.p, s.point.ng), s.pdf, 1e-4f * s.pdf);
    EXPECT_EQ(set.pdf_area(g, 0, kRef, s.point.p, s.point.ng, s.pick_sum),
              set.pdf_area(g, 0, kRef, s.point.p, s.point.ng));
    EXPECT_EQ(set.emitted(g, 0, {0, 0}, s.point.ng, -s.wi), s.radiance);
  }
  EXPECT_GT(area, 150);
  EXPECT_GT(environment, 150);
}

TEST(LightSet, EnvironmentMixtureMatchesPdfChiSquare) {
  // A constant and an envmap light: sample() picks one of them but reports the directions'
  // combined density; the directions must follow it.
  const LightSet set({}, {light_of(LightKind::constant, {0.5, 0.5, 0.5}), sky()}, sky_reader(),
                     kNoTextures, 1.0f);
  test::UniformFloats u(23);
  const auto sample = [&]() -> std::optional<glm::vec3> {
    const LightSample s = set.sample(kRef, u.next(), u.next2());
    if (!(s.pdf > 0)) return std::nullopt;
    return s.wi;
  };
  const test::DirectionChiSquareResult r =
      test::chi_square_directions(test::envmap_cell_bins(8, 5, 2), 100000, sample,
                                  [&](glm::vec3 d) {
                                    return double(set.pdf_environment(kRef, d));
                                  });
  EXPECT_GT(r.p_value, test::kChiSquareLevel) << r.detail;
}

TEST(LightSet, EstimatesTheIrradianceOfEveryLightTogether) {
  // E[radiance * cos / pdf] over sample() is the unoccluded irradiance from all lights: the
  // pick probabilities and every light's density must be right for it to come out.
  const Geometry quad = ceiling_quad(0, 3.0f);
  const glm::dmat4 sun_to_world =
      glm::rotate(glm::dmat4(1.0), glm::radians(160.0), glm::dvec3(0, 1, 0));
  Light rotated_sky = sky();
  rotated_sky.to_world = glm::rotate(glm::dmat4(1.0), glm::radians(70.0), glm::dvec3(1, 0, 1));
  const LightSet set(
      {&quad},
      {light_of(LightKind::point, {1, 1, 1}, glm::translate(glm::dmat4(1.0), {0.5, 0.5, 2})),
       light_of(LightKind::directional, {0.7, 0.7, 0.7}, sun_to_world),
       light_of(LightKind::constant, {0.2, 0.2, 0.2}), rotated_sky},
      sky_reader(), kNoTextures, 2.0f);
  const glm::dvec3 p(kRef.p), n(0, 0, 1);

  double expected = test::polygon_irradiance({{-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}}, p, n, 3.0);
  const glm::dvec3 to_point = glm::dvec3(0.5, 0.5, 2) - p;
  expected += glm::dot(glm::normalize(to_point), n) / glm::dot(to_point, to_point);
  expected += 0.7 * -glm::dvec3(sun_to_world[2]).z;
  // Constant and envmap by quadrature over the upper hemisphere (cos theta, phi).
  const int nc = 400, np = 800;
  for (int i = 0; i < nc; ++i) {
    const double c = (i + 0.5) / nc, s = std::sqrt(1 - c * c);
    for (int j = 0; j < np; ++j) {
      const double phi = 2 * M_PI * (j + 0.5) / np;
      const glm::vec3 l =
          set.environment(glm::vec3(float(s * std::cos(phi)), float(s * std::sin(phi)), float(c)));
      expected += double(l.y) * c * (2 * M_PI / (double(nc) * np));  // grey lights: y channel
    }
  }

  test::UniformFloats u(25);
  const int count = 200000;
  double sum = 0, sum2 = 0;
  for (int i = 0; i < count; ++i) {
    const LightSample s = set.sample(kRef, u.next(), u.next2());
    if (!(s.pdf > 0)) continue;
    const double f = double(s.radiance.y) * std::max(0.0, glm::dot(glm::dvec3(s.wi), n)) / s.pdf;
    sum += f;
    sum2 += f * f;
  }
  const double mean = sum / count, se = std::sqrt((sum2 / count - mean * mean) / count);
  EXPECT_NEAR(mean, expected, 5 * se + 1e-3 * expected) << "se " << se;
}

/// A spot light of intensity `intensity` at (0, 0, 5) shining down -z, beam 20 and cutoff 30
/// degrees.
Light spot_down(glm::dvec3 intensity) {
  glm::dmat4 to_world = glm::translate(glm::dmat4(1.0), {0, 0, 5});
  to_world = glm::rotate(to_world, glm::radians(180.0), glm::dvec3(1, 0, 0));
  Light l = light_of(LightKind::spot, intensity, to_world);
  l.cutoff_angle_deg = 30;
  l.beam_width_deg = 20;
  return l;
}

/// The point on z = 0 seen from the spot_down light at `theta_deg` off its axis (normal +z).
SurfacePoint below_spot(double theta_deg) {
  return {{float(5 * std::tan(glm::radians(theta_deg))), 0.0f, 0.0f}, {0, 0, 0}, {0, 0, 1}};
}

TEST(LightSet, ASpotLightWeighsAsThePointLightOfItsIntensityInsideItsCone) {
  // Beside a dim constant environment, a narrow spot must keep the pick probability a point
  // light of its intensity would have where it shines (the two weighed by their irradiance
  // bounds, I / d^2 against pi L; weighed by its power, 2 pi (1 - cos) I, the spot got 6 % of
  // the picks below it), and none where it cannot shine, where the environment gets them all.
  const glm::dvec3 intensity(10, 10, 10);
  const Light point =
      light_of(LightKind::point, intensity, glm::translate(glm::dmat4(1.0), {0, 0, 5}));
  const Light constant = light_of(LightKind::constant, {0.1, 0.1, 0.1});
  const LightSet with_spot({}, {spot_down(intensity), constant}, test::reader_of("x", ""),
                           kNoTextures, 5.0f);
  const LightSet with_point({}, {point, constant}, test::reader_of("x", ""), kNoTextures, 5.0f);
  const float constant_pdf = 1.0f / (4.0f * kPi);  // uniform over the sphere
  const glm::vec3 up(0, 0, 1);
  const auto environment_pick = [&](const LightSet& set, double theta_deg) {
    return set.pdf_environment(below_spot(theta_deg), up) / constant_pdf;
  };
  for (const double theta : {0.0, 10.0, 19.0}) {
    EXPECT_NEAR(environment_pick(with_spot, theta), environment_pick(with_point, theta), 1e-5f)
        << "theta " << theta;
  }
  const double irradiance_spot = 10.0 / 25.0, irradiance_constant = M_PI * 0.1;
  EXPECT_NEAR(environment_pick(with_spot, 0.0),
              irradiance_constant / (irradiance_spot + irradiance_constant), 1e-5);
  // On the ramp to the cutoff: still picked; beyond it (past the slack): never.
  EXPECT_LT(environment_pick(with_spot, 29.0), 1.0f);
  EXPECT_NEAR(environment_pick(with_spot, 31.0), 1.0f, 1e-6f);
  EXPECT_NEAR(environment_pick(with_spot, 60.0), 1.0f, 1e-6f);
  test::UniformFloats u(27);
  for (int i = 0; i < 200; ++i) {
    EXPECT_FALSE(with_spot.sample(below_spot(31.0), u.next(), u.next2()).delta);
  }
}

/// E[radiance.y * cos / pdf] over 100,000 of set.sample() at `ref` (normal `n`): the irradiance
/// the light sample estimates, and the estimate's standard error.
std::pair<double, double> irradiance_estimate(const LightSet& set, const SurfacePoint& ref,
                                              const glm::dvec3& n, uint32_t seed) {
  test::UniformFloats u(seed);
  const int count = 100000;
  double sum = 0, sum2 = 0;
  for (int i = 0; i < count; ++i) {
    const LightSample s = set.sample(ref, u.next(), u.next2());
    if (!(s.pdf > 0)) continue;
    const double f = double(s.radiance.y) * std::max(0.0, glm::dot(glm::dvec3(s.wi), n)) / s.pdf;
    sum += f;
    sum2 += f * f;
  }
  const double mean = sum / count;
  return {mean, std::sqrt((sum2 / count - mean * mean) / count)};
}

TEST(LightSet, EstimatesASpotLightAndTheEnvironmentTogether) {
  // E[radiance * cos / pdf] over sample() is the spot's I falloff cos / d^2 plus the
  // constant's pi L, inside the beam, on the ramp and outside the cone.
  const LightSet set({}, {spot_down({10, 10, 10}), light_of(LightKind::constant, {0.1, 0.1, 0.1})},
                     test::reader_of("x", ""), kNoTextures, 5.0f);
  const glm::dvec3 n(0, 0, 1);
  for (const double theta : {5.0, 25.0, 40.0}) {
    const SurfacePoint ref = below_spot(theta);
    const double d = 5 / std::cos(glm::radians(theta));
    const double falloff = theta <= 20 ? 1.0 : theta >= 30 ? 0.0 : (30 - theta) / 10;
    const double expected = 10 * falloff * std::cos(glm::radians(theta)) / (d * d) + M_PI * 0.1;
    const auto [mean, se] = irradiance_estimate(set, ref, n, 28);
    EXPECT_NEAR(mean, expected, 5 * se + 1e-4 * expected) << "theta " << theta << ", se " << se;
  }
}

TEST(LightSet, AProjectorWeighsAsThePointLightOfItsIntensityInsideItsFrustum) {
  // A projector of irradiance 10 at (0, 0, 5) shining down -z, fov 60 degrees, square image
  // (its corners 39.2 degrees off the axis), beside a dim constant environment: on the axis
  // picked as a point light of intensity pi 10 (their irradiance bounds, pi 10 / d^2 against
  // pi L), outside the cone through the corners never; and the estimate stays unbiased.
  glm::dmat4 to_world = glm::translate(glm::dmat4(1.0), {0, 0, 5});
  to_world = glm::rotate(to_world, glm::radians(180.0), glm::dvec3(1, 0, 0));
  Light projector = light_of(LightKind::projector, {10, 10, 10}, to_world);
  projector.fov_x_deg = 60;
  projector.aspect = 1;
  const LightSet set({}, {projector, light_of(LightKind::constant, {0.1, 0.1, 0.1})},
                     test::reader_of("x", ""), kNoTextures, 5.0f);
  const float constant_pdf = 1.0f / (4.0f * kPi);
  const glm::vec3 up(0, 0, 1);
  const double irradiance_projector = M_PI * 10 / 25, irradiance_constant = M_PI * 0.1;
  EXPECT_NEAR(set.pdf_environment(below_spot(0.0), up) / constant_pdf,
              irradiance_constant / (irradiance_projector + irradiance_constant), 1e-5);
  EXPECT_NEAR(set.pdf_environment(below_spot(41.0), up) / constant_pdf, 1.0f, 1e-6f);

  const glm::dvec3 n(0, 0, 1);
  for (const double theta : {0.0, 25.0, 45.0}) {
    const SurfacePoint ref = below_spot(theta);
    // On z = 0 the image is pi E / z^2 wherever it falls (within 30 degrees along x).
    const double expected = (theta < 30 ? M_PI * 10 / 25 : 0.0) + M_PI * 0.1;
    const auto [mean, se] = irradiance_estimate(set, ref, n, 29);
    EXPECT_NEAR(mean, expected, 5 * se + 1e-4 * expected) << "theta " << theta << ", se " << se;
  }
}

TEST(LightSet, NonEmittersGiveNothing) {
  const Geometry quad = ceiling_quad(0, 3.0f);
  Geometry wall = ceiling_quad(-1, 0.0f);
  const LightSet set({&quad}, {}, test::reader_of("x", ""), kNoTextures, 1.0f);
  EXPECT_EQ(set.emitted(wall, 0, {0, 0}, {0, 0, -1}, {0, 0, -1}), glm::vec3(0.0f));
  EXPECT_EQ(set.pdf_area(wall, 0, kRef, {0, 0, 1}, {0, 0, -1}), 0.0f);
  EXPECT_EQ(set.emitted(quad, 0, {0, 0}, {0, 0, -1}, {0, 0, -1}), glm::vec3(3.0f));
  EXPECT_GT(set.pdf_area(quad, 0, kRef, {0, 0, 1}, {0, 0, -1}), 0.0f);
}

TEST(LightSet, BlackEnvironmentBesideAPointLightStaysFinite) {
  Light black = sky();
  const LightSet set(
      {}, {black, light_of(LightKind::point, {1, 1, 1})},
      test::reader_of("sky.exr", test::exr_bytes(4, 3, std::vector<float>(36, 0.0f))), kNoTextures,
      1.0f);
  test::UniformFloats u(24);
  for (int i = 0; i < 100; ++i) {
    const LightSample s = set.sample(kRef, u.next(), u.next2());
    EXPECT_TRUE(s.pdf == 0 || (s.delta && s.pdf == 1.0f));
    EXPECT_TRUE(std::isfinite(s.radiance.x));
  }
  EXPECT_EQ(set.pdf_environment(kRef, {0, 1, 0}), 0.0f);
}

TEST(LightSet, AreaEmittersMustBeNumberedInOrder) {
  const Geometry quad = ceiling_quad(1, 3.0f);
  EXPECT_THROW(LightSet({&quad}, {}, test::reader_of("x", ""), kNoTextures, 1.0f),
               std::invalid_argument);
}

TEST(LightSet, BadLightsAreRefusedWithTheirOrigin) {
  std::vector<float> rgb(8 * 5 * 3, 1.0f);
  rgb[7] = -2.0f;
  try {
    LightSet set({}, {sky()}, test::reader_of("sky.exr", test::exr_bytes(8, 5, rgb)), kNoTextures,
                 1.0f);
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(
        std::string(e.what()).find("lights[4]: sky.exr: texel (x 2, y 0) channel G is negative"),
        std::string::npos)
        << e.what();
  }
  try {  // the reader's own error names the missing file
    LightSet set({}, {sky()}, test::reader_of("other.exr", ""), kNoTextures, 1.0f);
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("sky.exr"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tessera
