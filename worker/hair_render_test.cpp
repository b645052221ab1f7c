// Hair through the whole renderer: B-spline strands inside a constant environment. Without
// absorption the fibres only redirect light, so the image stays at most the environment's
// radiance (Mitsuba's hair loses a few per cent at each scattering, never gains); pigments
// darken it; the roughness extremes render without NaN or Inf. And a Mitsuba scene of hair
// strands (tests/data/mitsuba/hair/strands.xml) read by the importer and rendered as
// `tessera-worker render` renders it matches Mitsuba 3.9.1's image mean
// (mitsuba_hair_scene.py -> mitsuba_hair_scene.txt).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>

#include "accum/film.h"
#include "job/job_options.h"
#include "local_render.h"
#include "mitsuba_mean_test_support.h"
#include "render/renderer.h"
#include "render/test_statistics.h"
#include "scene/loader/scene_loader.h"

namespace tessera {
namespace {

/// Five wavy strands (uniform cubic B-splines of 8 points, radius 0.06) across the view of a
/// camera at (0, 0, 3), in a constant environment of radiance 1, all of material 0: `hair`.
Scene strands(const HairParameters& hair) {
  Scene s;
  s.camera.position = {0, 0, 3};
  s.camera.look_at = {0, 0, 0};
  s.camera.fov_deg = 30;
  Material m;
  m.name = "hair";
  m.type = MaterialType::hair;
  m.ior = 1.55 / 1.000277;
  m.hair = hair;
  s.materials.push_back(m);
  Shape c;
  c.kind = Shape::Kind::curves;
  c.curve_basis = CurveBasis::bspline;
  c.origin = "strands";
  for (int k = 0; k < 5; ++k) {
    for (int i = 0; i < 8; ++i) {
      const double y = -1.2 + 2.4 * i / 7.0;
      c.control_points.emplace_back(-0.5 + 0.25 * k + 0.08 * std::sin(3 * y + k), y,
                                    0.1 * std::cos(2 * y + k), 0.06);
    }
    c.curve_sizes.push_back(8);
  }
  s.shapes.push_back(c);
  Light sky;
  sky.kind = LightKind::constant;
  sky.value = glm::dvec3(1.0);
  s.lights.push_back(sky);
  return s;
}

HairParameters hair(glm::dvec3 sigma_a, double beta_m, double beta_n) {
  HairParameters h;
  h.sigma_a = {sigma_a, -1};
  h.longitudinal_roughness = beta_m;
  h.azimuthal_roughness = beta_n;
  return h;
}

test::Estimate render_mean(const Scene& scene, int spp, Accumulation* out = nullptr) {
  const Renderer renderer(scene, test::test_job(32, 32, uint32_t(spp)));
  Accumulation acc = renderer.render({0, 0, 32, 32}, 0, uint32_t(spp), nullptr);
  EXPECT_TRUE(test::all_finite(acc)) << acc.nan_dropped << " NaN, " << acc.inf_dropped << " Inf";
  const test::Estimate e = test::mean_luminance(acc);
  if (out) *out = std::move(acc);
  return e;
}

TEST(HairRender, ClearFibresInAFurnaceStayBelowTheEnvironment) {
  for (double beta : {0.2, 0.6}) {
    const test::Estimate e = render_mean(strands(hair(glm::dvec3(0), beta, beta)), 64);
    EXPECT_LE(e.mean, 1.0 + test::tolerance(e, 1.0)) << "beta " << beta;
    // A few per cent lost per scattering, the background exactly 1: well above 0.9.
    EXPECT_GE(e.mean, 0.9) << "beta " << beta;
  }
}

TEST(HairRender, PigmentsDarkenAndExtremesStayFinite) {
  const test::Estimate clear = render_mean(strands(hair(glm::dvec3(0), 0.3, 0.3)), 16);
  const test::Estimate brown = render_mean(strands(HairParameters()), 16);
  EXPECT_LT(brown.mean + test::tolerance(clear, brown), clear.mean);
  for (double beta : {0.0, 1e-3, 1.0}) {
    for (double sigma : {0.0, 1e3}) {
      render_mean(strands(hair(glm::dvec3(sigma), beta, 1.0 - beta)), 4);
    }
  }
}

TEST(HairRender, StrandsSceneMatchesMitsuba) {
  const std::string dir = std::string(TESSERA_SOURCE_DIR);
  const auto means = mitsuba_mean::read_mitsuba_means(dir + "/worker/render/bsdf/mitsuba_hair_scene.txt");
  ASSERT_EQ(means.count(""), 1u);
  const Scene scene = load_scene_file(dir + "/tests/data/mitsuba/hair/strands.xml");
  const JobOptions options = resolve_job_options(scene, {});
  ASSERT_EQ(options.width, 48);
  ASSERT_EQ(options.height, 64);
  ASSERT_EQ(options.max_depth, 16);
  mitsuba_mean::expect_mean_matches_mitsuba(scene, 32, 2, means.at(""), "strands.xml");
}

}  // namespace
}  // namespace tessera
