// Renders with known answers: the white furnace, the irradiance under a square light, and
// objects inside a constant environment.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "render/testing/test_scenes.h"
#include "renderer.h"
#include "test_statistics.h"
#include "texture/texture_test_images.h"

namespace tessera {
namespace {

JobOptions small_job(int w, int h, uint32_t spp, int max_depth = -1) {
  JobOptions o;
  o.width = w;
  o.height = h;
  o.spp = spp;
  o.max_depth = max_depth;
  o.seed = 11;
  o.tile_size = 64;
  o.batch_spp = spp;
  return o;
}

/// Mean radiance per channel over the accumulation, and the largest pixel deviation.
glm::dvec3 mean_rgb(const Accumulation& acc) {
  glm::dvec3 sum(0.0);
  uint64_t n = 0;
  for (size_t i = 0; i < acc.pixels(); ++i) {
    sum += glm::dvec3(acc.rgb[i * 3], acc.rgb[i * 3 + 1], acc.rgb[i * 3 + 2]);
    n += acc.count[i];
  }
  return sum / double(n);
}

Scene furnace_scene(bool sphere_enclosure, double albedo, double le, double scale) {
  Scene s;
  s.camera.position = {0.1 * scale, 0.05 * scale, 0.2 * scale};
  s.camera.look_at = {0.3 * scale, -0.2 * scale, -0.5 * scale};
  s.camera.fov_deg = 90;
  const uint32_t m = test::add_diffuse(s, {albedo, albedo, albedo});
  Shape enclosure = sphere_enclosure
                        ? test::sphere({0, 0, 0}, scale, m, /*inward=*/true)
                        : test::box({-scale, -scale, -scale}, {scale, scale, scale}, m, true);
  enclosure.emission = {le, le, le};
  s.shapes.push_back(enclosure);
  return s;
}

struct FurnaceCase {
  bool sphere;
  double albedo;
  double scale;
};

class WhiteFurnace : public ::testing::TestWithParam<FurnaceCase> {};

TEST_P(WhiteFurnace, ConvergesToEmissionOverOneMinusAlbedo) {
  const FurnaceCase c = GetParam();
  const double le = 0.7;
  const Scene s = furnace_scene(c.sphere, c.albedo, le, c.scale);
  // Inside a sphere, next-event estimation is exact (cos cos / d^2 is constant over the
  // sphere), so the estimator is nearly noise-free. In a box, light points near an edge of the
  // shading face make 1/d^2 heavy-tailed: unbiased, but it needs many more samples.
  // Albedo 0.8 makes paths long and their length (roulette) noisy: at 512 spp the image mean
  // strays past 1 % for about 1 in 5 seeds and some pixel past 6 % for most (measured with two
  // samplers alike, 24 seeds), so it takes 4096.
  const uint32_t spp = c.sphere ? (c.albedo >= 0.8 ? 4096 : 512) : 16384;
  const double pixel_tolerance = c.sphere ? 0.06 : 0.12;
  const Renderer renderer(s, small_job(4, 4, spp));
  const Accumulation acc = renderer.render({0, 0, 4, 4}, 0, spp);
  const double expected = le / (1.0 - c.albedo);
  const glm::dvec3 mean = mean_rgb(acc);
  for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(mean[ch], expected, 0.01 * expected);
  for (size_t i = 0; i < acc.pixels(); ++i) {
    EXPECT_NEAR(acc.rgb[i * 3] / acc.count[i], expected, pixel_tolerance * expected) << "pixel " << i;
  }
  EXPECT_EQ(acc.nan_dropped + acc.inf_dropped, 0u);
}

INSTANTIATE_TEST_SUITE_P(Enclosures, WhiteFurnace,
                         ::testing::Values(FurnaceCase{true, 0.5, 1.0}, FurnaceCase{false, 0.5, 1.0},
                                           FurnaceCase{true, 0.8, 1.0}, FurnaceCase{false, 0.8, 1e-3},
                                           FurnaceCase{true, 0.3, 1e4}));

/// Irradiance at a point h below the corner of a parallel a x b rectangle of radiance Le,
/// divided by Le: pi times the differential-area-to-rectangle form factor (Howell's catalogue
/// of configuration factors, B-3).
double corner_irradiance_over_le(double a, double b, double h) {
  const double x = a / h, y = b / h;
  const double sx = std::sqrt(1 + x * x), sy = std::sqrt(1 + y * y);
  return 0.5 * (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy));
}

TEST(DirectLighting, IrradianceUnderASquareLightMatchesTheClosedForm) {
  // A Lambertian floor of albedo rho under a square light of side 2 at height h, centred
  // above the origin; the camera looks at the origin from the side through a 1-pixel,
  // 0.01-degree view, so the pixel's radiance is rho / pi * E(origin).
  const double h = 1.5, half = 1.0, rho = 0.6, le = 3.0;
  Scene s;
  const uint32_t floor_m = test::add_diffuse(s, {rho, rho, rho});
  const uint32_t light_m = test::add_diffuse(s, {0, 0, 0});
  s.shapes.push_back(test::quad({-50, 0, 50}, {50, 0, 50}, {50, 0, -50}, {-50, 0, -50}, floor_m));
  Shape light = test::quad({-half, h, -half}, {half, h, -half}, {half, h, half}, {-half, h, half},
                           light_m);  // counter-clockwise seen from below: faces down
  light.emission = {le, le, le};
  s.shapes.push_back(light);
  s.camera.position = {4.0, 0.5, 0.0};
  s.camera.look_at = {0, 0, 0};
  s.camera.fov_deg = 0.01;

  const double e_over_le = 4.0 * corner_irradiance_over_le(half, half, h);
  const double expected = rho / M_PI * le * e_over_le;
  const Renderer renderer(s, small_job(1, 1, 1 << 16, 2));
  const Accumulation acc = renderer.render({0, 0, 1, 1}, 0, 1 << 16);
  EXPECT_NEAR(acc.rgb[0] / acc.count[0], expected, 0.003 * expected);
}

// Mitsuba's mask on the same floor: a camera ray passes through with probability 1 - opacity
// and sees nothing below (black), else the floor reflects all its light, so the pixel is opacity
// times the opaque floor's. Both shading paths: the plain Lambertian one (constant opacity) and
// the general one (opacity from a texture). Counting opacity twice in the light sample gave
// opacity^2 times: half and a quarter of the answer here.
TEST(DirectLighting, AMaskedFloorReflectsOpacityTimesTheLight) {
  const double h = 1.5, half = 1.0, rho = 0.6, le = 3.0;
  const double e_over_le = 4.0 * corner_irradiance_over_le(half, half, h);
  for (const double opacity : {0.5, 0.25}) {
    for (const bool textured : {false, true}) {
      Scene s;
      const uint32_t floor_m = test::add_diffuse(s, {rho, rho, rho});
      const uint32_t light_m = test::add_diffuse(s, {0, 0, 0});
      if (textured) {
        Texture t;
        t.name = "opacity";
        t.origin = "test";
        t.kind = TextureKind::rawconstant;
        t.value = {opacity, opacity, opacity};
        t.channels = 1;
        s.textures.push_back(t);
        s.materials[floor_m].opacity = {1.0, 0};
      } else {
        s.materials[floor_m].opacity = {opacity, -1};
      }
      s.shapes.push_back(test::quad({-50, 0, 50}, {50, 0, 50}, {50, 0, -50}, {-50, 0, -50}, floor_m));
      Shape light = test::quad({-half, h, -half}, {half, h, -half}, {half, h, half}, {-half, h, half},
                               light_m);
      light.emission = {le, le, le};
      s.shapes.push_back(light);
      s.camera.position = {4.0, 0.5, 0.0};
      s.camera.look_at = {0, 0, 0};
      s.camera.fov_deg = 0.01;
      const double expected = opacity * rho / M_PI * le * e_over_le;
      const Renderer renderer(s, small_job(1, 1, 1 << 16, 2));
      const Accumulation acc = renderer.render({0, 0, 1, 1}, 0, 1 << 16);
      EXPECT_NEAR(acc.rgb[0] / acc.count[0], expected, 0.01 * expected)
          << "opacity " << opacity << (textured ? ", textured" : ", constant");
    }
  }
}

TEST(DirectLighting, NoEmittersRendersBlackAndTracesNoShadowRays) {
  Scene s;
  const uint32_t m = test::add_diffuse(s, {0.8, 0.8, 0.8});
  s.shapes.push_back(test::box({-1, -1, -1}, {1, 1, 1}, m, true));
  // Mirror and glass too: specular paths count emission, and there is none to count.
  s.shapes.push_back(test::sphere({-0.4, -0.5, -0.6}, 0.3, test::add_material(s, MaterialType::mirror)));
  s.shapes.push_back(test::sphere({0.4, -0.5, -0.6}, 0.3, test::add_material(s, MaterialType::glass, 1.5)));
  s.camera.position = {0, 0, 0};
  s.camera.look_at = {0, 0, -1};
  const Renderer renderer(s, small_job(4, 4, 16));
  RenderStats stats;
  const Accumulation acc = renderer.render({0, 0, 4, 4}, 0, 16, &stats);
  for (double v : acc.rgb) EXPECT_EQ(v, 0.0);
  EXPECT_EQ(stats.shadow_rays, 0u);
  EXPECT_GT(stats.rays, 0u);
}

TEST(DirectLighting, OneSidedLightIsDarkBehind) {
  // The camera sees the back of a one-sided light: black. Two-sided: its radiance.
  for (bool two_sided : {false, true}) {
    Scene s;
    const uint32_t m = test::add_diffuse(s, {0, 0, 0});
    Shape light = test::quad({-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, m);  // faces +z
    light.emission = {2, 2, 2};
    light.two_sided_emission = two_sided;
    s.shapes.push_back(light);
    s.camera.position = {0, 0, -3};
    s.camera.look_at = {0, 0, 0};
    s.camera.fov_deg = 10;
    const Renderer renderer(s, small_job(2, 2, 4));
    const Accumulation acc = renderer.render({0, 0, 2, 2}, 0, 4);
    EXPECT_EQ(acc.rgb[0] / acc.count[0], two_sided ? 2.0 : 0.0);
  }
}

// --- Inside a constant environment ------------------------------------------------------------
//
// A convex object in an environment of radiance L everywhere: every point of it sees the whole
// environment over its hemisphere (nothing else), so a diffuse surface of albedo a shows exactly
// a * L, and a lossless specular one (a mirror, a smooth conductor of reflectance 1, a smooth or
// thin dielectric) shows L, whichever way its paths go: it is invisible. The environment is
// Mitsuba's constant emitter, or an environment map whose texels are all L (the same light,
// importance-sampled through its map). Tolerances: test_statistics.h, 5 standard errors
// estimated from the samples plus float rounding; depth unbounded (Russian roulette included).

enum class Environment { constant, envmap };

/// The object of material `m` (a sphere of radius 1 at the origin) in the environment, seen
/// from 4 away through a 20-degree view, so that every pixel sees the sphere. Returns the scene
/// and, for the envmap, the reader serving its 8 x 4 map.
Scene environment_scene(Environment env, double le, Material m, FileReader* reader) {
  Scene s;
  s.camera.position = {0.3, 0.2, 4};
  s.camera.look_at = {0, 0, 0};
  s.camera.fov_deg = 20;
  m.name = "object";
  s.materials.push_back(m);
  s.shapes.push_back(test::sphere({0, 0, 0}, 1.0, 0));
  Light light;
  light.origin = "lights[0]";
  if (env == Environment::constant) {
    light.kind = LightKind::constant;
    light.value = {le, le, le};
  } else {
    light.kind = LightKind::envmap;
    light.file = "env.exr";
    light.value = {1, 1, 1};
    const std::vector<float> texels(8 * 4 * 3, float(le));
    *reader = test::memory_reader(
        {{"env.exr", test::encode_image("env.exr", 8, 4, 3, texels, OIIO::TypeDesc::FLOAT)}});
  }
  s.lights.push_back(light);
  return s;
}

struct EnvironmentCase {
  const char* name;
  MaterialType type;
  double albedo;   ///< diffuse: reflectance
  double ior;      ///< glass kinds
  bool perfect;    ///< conductor: Fresnel reflectance 1
  double expected; ///< what every pixel shows, over L
};

class InConstantEnvironment
    : public ::testing::TestWithParam<std::tuple<EnvironmentCase, Environment>> {};

TEST_P(InConstantEnvironment, EveryPixelShowsTheClosedForm) {
  const auto& [c, env] = GetParam();
  const double le = 0.8;
  Material m;
  m.type = c.type;
  m.reflectance.value = {c.albedo, c.albedo, c.albedo};
  m.ior = c.ior;
  m.perfect = c.perfect;
  FileReader reader;
  const Scene s = environment_scene(env, le, m, &reader);
  const uint32_t spp = 4096;  // a diffuse sphere's image mean to 0.1 % (1 standard error)
  const Renderer renderer(s, test::test_job(4, 4, spp), reader);
  const Accumulation acc = renderer.render({0, 0, 4, 4}, 0, spp);
  EXPECT_TRUE(test::all_finite(acc));
  const double expected = c.expected * le;
  const test::Estimate e = test::mean_luminance(acc);
  std::printf("%s: mean %.6f, expected %.6f, SE %.2e\n", c.name, e.mean, expected, e.se);
  EXPECT_NEAR(e.mean, expected, test::tolerance(e, expected));
  // Every pixel estimates the same value. A glass pixel's samples are mostly exactly L, with
  // rare long paths weighted up by Russian roulette; at this spp one pixel may have drawn too
  // few of those to estimate its own variance, so the pooled standard error of a pixel (the
  // mean variance over pixels) is used when it is larger.
  const double pooled_se = e.se * std::sqrt(double(acc.pixels()));
  for (size_t i = 0; i < acc.pixels(); ++i) {
    test::Estimate p = test::pixel_luminance(acc, i);
    p.se = std::max(p.se, pooled_se);
    EXPECT_NEAR(p.mean, expected, test::tolerance(p, expected)) << "pixel " << i;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Analytic, InConstantEnvironment,
    ::testing::Combine(
        ::testing::Values(
            EnvironmentCase{"diffuse_albedo_0_3", MaterialType::diffuse, 0.3, 1.5, false, 0.3},
            EnvironmentCase{"diffuse_albedo_0_8", MaterialType::diffuse, 0.8, 1.5, false, 0.8},
            EnvironmentCase{"diffuse_albedo_1", MaterialType::diffuse, 1.0, 1.5, false, 1.0},
            EnvironmentCase{"mirror", MaterialType::mirror, 0, 1.5, false, 1.0},
            EnvironmentCase{"conductor_reflectance_1", MaterialType::conductor, 0, 1.5, true, 1.0},
            EnvironmentCase{"dielectric_1_5", MaterialType::glass, 0, 1.5, false, 1.0},
            EnvironmentCase{"dielectric_1_0001", MaterialType::glass, 0, 1.0001, false, 1.0},
            EnvironmentCase{"dielectric_3", MaterialType::glass, 0, 3.0, false, 1.0},
            EnvironmentCase{"thindielectric_1_5", MaterialType::thin_glass, 0, 1.5, false, 1.0}),
        ::testing::Values(Environment::constant, Environment::envmap)),
    [](const auto& info) {
      return std::string(std::get<0>(info.param).name) +
             (std::get<1>(info.param) == Environment::constant ? "_constant" : "_envmap");
    });

TEST(InConstantEnvironmentBackground, CameraRaysThatMissSeeTheRadiance) {
  // Seen from farther away the sphere leaves the corners of the image: there the camera sees
  // the environment itself, L exactly (no randomness), around a diffuse sphere showing a L.
  Material m;
  m.reflectance.value = {0.5, 0.5, 0.5};
  FileReader unused;
  Scene s = environment_scene(Environment::constant, 0.8, m, &unused);
  s.camera.position = {0, 0, 6};
  s.camera.fov_deg = 30;
  const int size = 8;
  const uint32_t spp = 64;
  const Renderer renderer(s, test::test_job(size, size, spp));
  const Accumulation acc = renderer.render({0, 0, size, size}, 0, spp);
  EXPECT_TRUE(test::all_finite(acc));
  for (int corner : {0, size - 1, size * (size - 1), size * size - 1}) {
    const test::Estimate p = test::pixel_luminance(acc, size_t(corner));
    EXPECT_NEAR(p.mean, 0.8, test::kFloatRounding) << "corner pixel " << corner;
  }
  const int centre = size / 2 * size + size / 2;
  const test::Estimate c = test::pixel_luminance(acc, size_t(centre));
  EXPECT_NEAR(c.mean, 0.4, test::tolerance(c, 0.4));
}

}  // namespace
}  // namespace tessera
