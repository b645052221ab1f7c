// The renderer at its extremes (docs/accuracy.md lists each test, what it checks and its
// tolerance). Every tolerance is a number of estimated standard errors (test_statistics.h) plus a
// float-rounding allowance; nothing depends on the machine's speed.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "accum/film.h"
#include "render/integrators/path_vertex.h"
#include "render/testing/test_scenes.h"
#include "renderer.h"
#include "scene/loader/scene_loader.h"
#include "test_statistics.h"

namespace tessera {
namespace {

using test::Estimate;

const std::string kSource = TESSERA_SOURCE_DIR;

// --- 1 spp: no NaN or Inf anywhere -------------------------------------------------------

TEST(Extremes, OneSppRendersWithoutNanOrInf) {
  // The example scenes with every material (diffuse, mirror, glass, meshes, spheres), 1 sample
  // per pixel, unbounded depth: the first samples of every pixel are finite and none is dropped.
  struct Case {
    const char* file;
    int width, height;
  };
  for (const Case c : {Case{"cornell.json", 64, 64}, Case{"hexroom.json", 96, 54},
                       Case{"cornell-sphere.json", 64, 64}}) {
    const Scene s = load_scene_file(kSource + "/scenes/" + c.file);
    const Renderer renderer(s, test::test_job(c.width, c.height, 1));
    RenderStats stats;
    const Accumulation acc = renderer.render({0, 0, c.width, c.height}, 0, 1, &stats);
    EXPECT_TRUE(test::all_finite(acc)) << c.file << ": " << acc.nan_dropped << " NaN, "
                                       << acc.inf_dropped << " Inf";
    for (uint32_t n : acc.count) ASSERT_EQ(n, 1u) << c.file;
    EXPECT_EQ(stats.samples, uint64_t(c.width) * uint64_t(c.height)) << c.file;
    EXPECT_GT(test::mean_luminance(acc).mean, 0.0) << c.file;
  }
}

// --- Accumulation over many batches: no drift --------------------------------------------

/// The white furnace sphere (albedo 0.5, unbounded depth: Russian roulette makes each sample
/// random, the closed form is le / (1 - albedo)), `spp` samples per pixel of a 4x4 image
/// rendered in `batches` batches merged in order. Shared with the 1,000,000-spp version in
/// tests/render/convergence_test.cpp.
TEST(Extremes, FurnaceAccumulatedOverManyBatchesHasNoDrift) {
  const double albedo = 0.5, le = 0.7;
  const uint32_t spp = 1 << 16, batch = 256;  // 256 batches
  const Renderer renderer(test::furnace_scene(true, albedo, le), test::test_job(4, 4, spp));
  const Accumulation acc = test::render_batches(renderer, spp, batch);
  const double expected = test::furnace_expected(albedo, le, -1);
  const Estimate e = test::mean_luminance(acc);
  std::printf("furnace, %u spp in %u batches: mean %.8f, expected %.8f, SE %.2e\n", spp,
              spp / batch, e.mean, expected, e.se);
  EXPECT_GT(e.se, 0.0);  // roulette makes the samples random: the test has teeth
  EXPECT_NEAR(e.mean, expected, test::tolerance(e, expected));
  for (size_t i = 0; i < acc.pixels(); ++i) {
    const Estimate p = test::pixel_luminance(acc, i);
    EXPECT_NEAR(p.mean, expected, test::tolerance(p, expected)) << "pixel " << i;
  }
  EXPECT_TRUE(test::all_finite(acc));
}

// --- Scale ---------------------------------------------------------------------------------

TEST(Extremes, SceneScaleDoesNotChangeTheImage) {
  // The Cornell box (meshes, a light, NEE) at scales 1e-3 and 1e4 against scale 1: the image
  // means agree within the noise of both renders.
  const Scene base = load_scene_file(kSource + "/scenes/cornell.json");
  const uint32_t spp = 64;
  const auto render_at = [&](double k) {
    const Scene s = test::scaled(base, k);
    const Renderer renderer(s, test::test_job(32, 32, spp));
    return renderer.render({0, 0, 32, 32}, 0, spp);
  };
  const Accumulation one = render_at(1.0);
  const Estimate e1 = test::mean_luminance(one);
  for (double k : {1e-3, 1e4}) {
    const Accumulation acc = render_at(k);
    const Estimate ek = test::mean_luminance(acc);
    std::printf("scale %g: mean %.6f, scale 1: %.6f (SE %.2e)\n", k, ek.mean, e1.mean, ek.se);
    EXPECT_TRUE(test::all_finite(acc)) << "scale " << k;
    EXPECT_NEAR(ek.mean, e1.mean, test::tolerance(ek, e1)) << "scale " << k;
  }
}

// --- Grazing camera rays -------------------------------------------------------------------

/// Irradiance over radiance at a point h below the corner of a parallel a x b rectangle of
/// uniform radiance (Howell's catalogue of configuration factors, B-3, times pi).
double corner_irradiance_over_le(double a, double b, double h) {
  const double x = a / h, y = b / h;
  const double sx = std::sqrt(1 + x * x), sy = std::sqrt(1 + y * y);
  return 0.5 * (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy));
}

/// The same for a point at (px, pz) under the axis-aligned rectangle [-half, half]^2 at height
/// h: the rectangle split into the four rectangles that meet above the point.
double rect_irradiance_over_le(double half, double h, double px, double pz) {
  double sum = 0;
  for (double a : {half - px, half + px}) {
    for (double b : {half - pz, half + pz}) sum += corner_irradiance_over_le(a, b, h);
  }
  return sum;
}

TEST(Extremes, GrazingCameraRaysOnAPlane) {
  // A camera 1e-3 above a diffuse plane looks at it at 0.1 to 0.9 degrees: every ray grazes it.
  // The plane is lit by a parallel square light (radiance le) at height 1, so the radiance of each
  // pixel is rho / pi * le * E/le at the point it sees (closed form). A camera ray that slipped
  // through the plane or its diagonal would escape (black), a shadow ray that hit the plane it
  // leaves would darken the pixel: either shows as a bias below the closed form.
  // The light is a 2 x 2 square centred above (0, -0.3), near the points seen (z from -0.06 to
  // -0.6), so that sampling it by area is not heavy-tailed.
  const double rho = 0.5, le = 1.0, h = 1.0, half = 1.0, cz = -0.3, cam_h = 1e-3;
  Scene s;
  const uint32_t floor_m = test::add_diffuse(s, {rho, rho, rho});
  const uint32_t black = test::add_diffuse(s, {0, 0, 0});
  s.shapes.push_back(test::quad({-100, 0, 100}, {100, 0, 100}, {100, 0, -100}, {-100, 0, -100}, floor_m));
  Shape light = test::quad({-half, h, cz - half}, {half, h, cz - half}, {half, h, cz + half},
                           {-half, h, cz + half}, black);
  light.emission = {le, le, le};
  s.shapes.push_back(light);
  const double down = 0.5 * M_PI / 180.0;  // look 0.5 degrees below the horizon
  s.camera.position = {0, cam_h, 0};
  s.camera.look_at = {0, cam_h - std::tan(down), -1};
  s.camera.fov_deg = 0.8;
  s.camera.fov_axis = FovAxis::y;

  const int size = 4;
  const uint32_t spp = 4096;
  const Renderer renderer(s, test::test_job(size, size, spp));
  const Accumulation acc = renderer.render({0, 0, size, size}, 0, spp);
  EXPECT_TRUE(test::all_finite(acc));
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      // The point the pixel centre sees; across a pixel E changes by < 1e-6 relative.
      const double fy = std::tan(0.4 * M_PI / 180.0) * (1.0 - 2.0 * (y + 0.5) / size);
      const double fx = std::tan(0.4 * M_PI / 180.0) * (2.0 * (x + 0.5) / size - 1.0);
      const double dy = fy * std::cos(down) - std::sin(down), dz = -(std::cos(down) + fy * std::sin(down));
      const double t = cam_h / -dy;
      const double expected = rho / M_PI * le * rect_irradiance_over_le(half, h, t * fx, t * dz - cz);
      const Estimate p = test::pixel_luminance(acc, size_t(y * size + x));
      EXPECT_NEAR(p.mean, expected, test::tolerance(p, expected)) << "pixel " << x << ", " << y;
    }
  }
}

// --- Glass: extreme indices and total internal reflection ----------------------------------

class GlassInFurnace : public ::testing::TestWithParam<double> {};

TEST_P(GlassInFurnace, IsInvisibleInAWhiteFurnace) {
  // A lossless dielectric in an isotropic radiance field L leaves it L outside (eta^2 L inside,
  // expanded back on the way out), so a glass sphere of any index inside a white furnace is
  // invisible: every pixel converges to le / (1 - albedo). Index 1.0001 is nearly index 1
  // (Fresnel ~1e-9), index 3 reflects 25 % at normal incidence and traps light by TIR inside.
  const double ior = GetParam(), albedo = 0.5, le = 1.0;
  Scene s = test::furnace_scene(true, albedo, le);
  s.camera.position = {0, 0, 0.8};
  s.camera.look_at = {0, 0, 0};
  s.camera.fov_deg = 60;
  s.shapes.push_back(test::sphere({0, 0, 0}, 0.4, test::add_material(s, MaterialType::glass, ior)));
  const uint32_t spp = 1024;
  const Renderer renderer(s, test::test_job(4, 4, spp));
  const Accumulation acc = renderer.render({0, 0, 4, 4}, 0, spp);
  const double expected = test::furnace_expected(albedo, le, -1);
  EXPECT_TRUE(test::all_finite(acc));
  const Estimate e = test::mean_luminance(acc);
  std::printf("IOR %g: mean %.5f, expected %.5f, SE %.2e\n", ior, e.mean, expected, e.se);
  EXPECT_NEAR(e.mean, expected, test::tolerance(e, expected));
  for (size_t i = 0; i < acc.pixels(); ++i) {
    const Estimate p = test::pixel_luminance(acc, i);
    EXPECT_NEAR(p.mean, expected, test::tolerance(p, expected)) << "pixel " << i;
  }
}

INSTANTIATE_TEST_SUITE_P(Extremes, GlassInFurnace, ::testing::Values(1.0001, 1.5, 3.0),
                         [](const auto& info) {
                           return "ior_" + std::to_string(int(std::lround(info.param * 10000)));
                         });

TEST(Extremes, PathsTrappedByTotalInternalReflectionEnd) {
  // The camera sits inside a glass sphere (index 1.5), 0.9 of the radius from its centre, and
  // looks along the tangent: every camera ray meets the surface at sin(theta) >= 0.88 > 1/1.5
  // and, the sphere being round, at that same angle forever after. No light can reach such a
  // path, so the image is exactly black; the path ends only by Russian roulette, whose survival
  // is capped at 0.95 from the fifth delta vertex in a row on (path_vertex.h spares the first
  // kFreeSpecularVertices = 4): closest-hit rays per sample are 1 + 4 + Geometric(0.05), mean
  // 1 + 4 + 19 = 24.
  Scene s = test::furnace_scene(true, 0.5, 1.0, 10.0);  // light all around, none gets in
  s.shapes.push_back(test::sphere({0, 0, 0}, 1.0, test::add_material(s, MaterialType::glass, 1.5)));
  s.camera.position = {0, 0, 0.9};
  s.camera.look_at = {1, 0, 0.9};
  s.camera.fov_deg = 20;
  const uint32_t spp = 256;
  const Renderer renderer(s, test::test_job(4, 4, spp));
  RenderStats stats;
  const Accumulation acc = renderer.render({0, 0, 4, 4}, 0, spp, &stats);
  EXPECT_TRUE(test::all_finite(acc));
  for (double v : acc.rgb) EXPECT_EQ(v, 0.0);
  const double n = double(stats.samples);
  const double mean_rays = double(stats.rays) / n;
  const double sd = std::sqrt(0.95) / 0.05;  // of a Geometric(0.05) count of survivals
  const double se = sd / std::sqrt(n);
  const double expected = 1.0 + path_vertex_detail::kFreeSpecularVertices + 0.95 / 0.05;
  std::printf("TIR: %.3f closest-hit rays per sample (expected %.0f, SE %.3f)\n", mean_rays, expected, se);
  EXPECT_NEAR(mean_rays, expected, test::kSigmas * se);
  EXPECT_EQ(stats.shadow_rays, 0u);
}

// --- A tiny, bright light ------------------------------------------------------------------

TEST(Extremes, TinyLightOfTheSamePowerGivesTheSameImage) {
  // A sphere light of radiance L and radius r irradiates every point that sees all of it like a
  // point light of intensity pi L r^2 at its centre: E = pi L r^2 cos / d^2. So a light of area
  // 1e-6 and one of radius 0.25 with the same power (same L r^2) give the same image of a
  // diffuse floor; the camera does not see the light. Both are checked against the closed form
  // rho L r^2 cos / d^2 and against each other.
  const double rho = 0.7, r_normal = 0.25, l_normal = 5.0;
  const double r_tiny = std::sqrt(1e-6 / (4 * M_PI));  // area 1e-6
  const double l_tiny = l_normal * (r_normal / r_tiny) * (r_normal / r_tiny);
  const glm::dvec3 c(0.5, 2.0, 0.3);
  const auto render_with = [&](double r, double l) {
    Scene s;
    const uint32_t floor_m = test::add_diffuse(s, {rho, rho, rho});
    s.shapes.push_back(test::quad({-50, 0, 50}, {50, 0, 50}, {50, 0, -50}, {-50, 0, -50}, floor_m));
    Shape light = test::sphere(c, r, test::add_diffuse(s, {0, 0, 0}));
    light.emission = {l, l, l};
    s.shapes.push_back(light);
    s.camera.position = {4.0, 0.5, 0.0};
    s.camera.look_at = {0, 0, 0};
    s.camera.fov_deg = 0.01;
    const uint32_t spp = 8192;
    const Renderer renderer(s, test::test_job(4, 4, spp));
    return renderer.render({0, 0, 4, 4}, 0, spp);
  };
  const double d = glm::length(c);
  const double expected = rho * l_normal * r_normal * r_normal * (c.y / d) / (d * d);
  const Accumulation normal = render_with(r_normal, l_normal);
  const Accumulation tiny = render_with(r_tiny, l_tiny);
  const Estimate en = test::mean_luminance(normal), et = test::mean_luminance(tiny);
  std::printf("tiny light: mean %.6f (SE %.1e), normal light %.6f (SE %.1e), closed form %.6f\n",
              et.mean, et.se, en.mean, en.se, expected);
  EXPECT_TRUE(test::all_finite(normal));
  EXPECT_TRUE(test::all_finite(tiny));
  EXPECT_NEAR(en.mean, expected, test::tolerance(en, expected));
  EXPECT_NEAR(et.mean, expected, test::tolerance(et, expected));
  EXPECT_NEAR(et.mean, en.mean, test::tolerance(et, en));
}

// --- Degenerate and needle triangles -------------------------------------------------------

/// The square [-s, s]^2 at height y as a fan of `n` needle triangles from the corner (-s, -s)
/// (aspect ratios up to ~n), facing up or down, with a zero-area triangle (a repeated vertex)
/// and a collinear one (three points on an edge) among them.
Shape needle_square(double s, double y, int n, bool facing_up, uint32_t material) {
  Shape sh;
  sh.kind = Shape::Kind::triangles;
  sh.material = material;
  sh.origin = "needles";
  sh.positions.push_back({-s, y, -s});
  // The far edges (s, z) and (x, s), walked from (s, -s) to (-s, s).
  for (int i = 0; i <= n; ++i) {
    const double t = 2.0 * double(i) / n;
    sh.positions.push_back(t <= 1 ? glm::dvec3(s, y, -s + 2 * s * t) : glm::dvec3(s - 2 * s * (t - 1), y, s));
  }
  for (uint32_t i = 1; i <= uint32_t(n); ++i) {
    // (0, i, i+1) winds clockwise seen from above (+y): facing down.
    sh.indices.push_back(facing_up ? glm::u32vec3(0, i + 1, i) : glm::u32vec3(0, i, i + 1));
  }
  sh.indices.push_back({1, 1, 2});  // zero area: a repeated vertex
  sh.indices.push_back({1, 2, 3});  // zero area: three points on the edge x = s
  return sh;
}

TEST(Extremes, DegenerateAndNeedleTrianglesRenderLikeAQuad) {
  // A floor and a light made of needle triangles (1000 and 200, aspect ratio up to ~1000:1)
  // with degenerate ones among them render like the same floor and light as two triangles.
  const auto scene = [](bool needles) {
    Scene s;
    const uint32_t floor_m = test::add_diffuse(s, {0.6, 0.6, 0.6});
    const uint32_t black = test::add_diffuse(s, {0, 0, 0});
    Shape floor = needles ? needle_square(2, 0, 1000, true, floor_m)
                          : test::quad({-2, 0, 2}, {2, 0, 2}, {2, 0, -2}, {-2, 0, -2}, floor_m);
    Shape light = needles ? needle_square(0.5, 1.5, 200, false, black)
                          : test::quad({-0.5, 1.5, -0.5}, {0.5, 1.5, -0.5}, {0.5, 1.5, 0.5},
                                       {-0.5, 1.5, 0.5}, black);
    light.emission = {4, 4, 4};
    s.shapes.push_back(floor);
    s.shapes.push_back(light);
    s.camera.position = {3.0, 1.0, 3.0};
    s.camera.look_at = {0, 0, 0};
    s.camera.fov_deg = 50;
    return s;
  };
  const uint32_t spp = 64;
  const Renderer quads(scene(false), test::test_job(16, 16, spp));
  const Renderer needles(scene(true), test::test_job(16, 16, spp));
  const Accumulation a = quads.render({0, 0, 16, 16}, 0, spp);
  const Accumulation b = needles.render({0, 0, 16, 16}, 0, spp);
  EXPECT_TRUE(test::all_finite(a));
  EXPECT_TRUE(test::all_finite(b));
  const Estimate ea = test::mean_luminance(a), eb = test::mean_luminance(b);
  std::printf("needles: mean %.6f (SE %.1e), quads %.6f (SE %.1e)\n", eb.mean, eb.se, ea.mean, ea.se);
  EXPECT_GT(ea.mean, 0.0);
  EXPECT_NEAR(eb.mean, ea.mean, test::tolerance(ea, eb));
  for (size_t i = 0; i < a.pixels(); ++i) {
    const Estimate pa = test::pixel_luminance(a, i), pb = test::pixel_luminance(b, i);
    EXPECT_NEAR(pb.mean, pa.mean, test::tolerance(pa, pb)) << "pixel " << i;
  }
}

// --- Huge radiance -------------------------------------------------------------------------

TEST(Extremes, RadianceOf1e30DoesNotOverflowTheSums) {
  // A white furnace emitting 1e30: samples of ~2e30, squared luminance ~4e60 and their sums stay
  // finite in double; the mean is le / (1 - albedo) within the noise, and the image (float)
  // holds it.
  const double albedo = 0.5, le = 1e30;
  const uint32_t spp = 256;
  const Renderer renderer(test::furnace_scene(true, albedo, le), test::test_job(4, 4, spp));
  const Accumulation acc = test::render_batches(renderer, spp, 16);
  EXPECT_TRUE(test::all_finite(acc));
  const double expected = test::furnace_expected(albedo, le, -1);
  const Estimate e = test::mean_luminance(acc);
  EXPECT_NEAR(e.mean, expected, test::tolerance(e, expected));
  EXPECT_TRUE(std::isfinite(estimate_relative_error({acc})));
  const RgbImage image = resolve_image(4, 4, {acc});
  for (float v : image.rgb) EXPECT_TRUE(std::isfinite(v));
}

}  // namespace
}  // namespace tessera
