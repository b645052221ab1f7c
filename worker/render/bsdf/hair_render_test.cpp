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
#include <fstream>
#include <sstream>
#include <string>

#include "accum/film.h"
#include "job/job_options.h"
#include "local_render.h"
#include "render/renderer.h"
#include "render/test_statistics.h"
#include "scene/scene_loader.h"

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

/// Per channel: the mean of `image` without a 2-pixel border (as mitsuba_hair_scene.py takes
/// Mitsuba's).
std::array<double, 3> inner_mean(const RgbImage& image) {
  std::array<double, 3> sum{0, 0, 0};
  int n = 0;
  for (int y = 2; y < image.height - 2; ++y) {
    for (int x = 2; x < image.width - 2; ++x, ++n) {
      for (int c = 0; c < 3; ++c) sum[c] += image.rgb[(size_t(y) * image.width + x) * 3 + c];
    }
  }
  for (double& v : sum) v /= n;
  return sum;
}

TEST(HairRender, StrandsSceneMatchesMitsuba) {
  const std::string dir = std::string(TESSERA_SOURCE_DIR);
  std::ifstream in(dir + "/worker/render/bsdf/mitsuba_hair_scene.txt");
  ASSERT_TRUE(in) << "cannot read mitsuba_hair_scene.txt";
  std::array<double, 3> mitsuba{}, mitsuba_se{};
  int channels = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream row(line);
    std::string name;
    ASSERT_TRUE(row >> name >> mitsuba[channels] >> mitsuba_se[channels]) << line;
    ++channels;
  }
  ASSERT_EQ(channels, 3);

  const Scene scene = load_scene_file(dir + "/tests/data/mitsuba/hair/strands.xml");
  // Two seeds: their difference per pixel gives the noise of Tessera's mean (as
  // scripts/mitsuba_sweep.py estimates it).
  const int kSpp = 32;
  std::array<RgbImage, 2> images;
  for (int seed = 0; seed < 2; ++seed) {
    JobOverrides overrides;
    overrides.spp = kSpp;
    overrides.seed = uint64_t(seed);
    const JobOptions options = resolve_job_options(scene, overrides);
    ASSERT_EQ(options.width, 48);
    ASSERT_EQ(options.height, 64);
    ASSERT_EQ(options.max_depth, 16);
    const LocalRenderResult result = render_job(scene, options);
    for (const Accumulation& t : result.tiles) {
      EXPECT_EQ(t.nan_dropped + t.inf_dropped, 0u);
    }
    images[seed] = resolve_image(options.width, options.height, result.tiles);
  }
  const std::array<double, 3> a = inner_mean(images[0]), b = inner_mean(images[1]);
  std::array<double, 3> diff2{0, 0, 0};
  int n = 0;
  for (int y = 2; y < 62; ++y) {
    for (int x = 2; x < 46; ++x, ++n) {
      for (int c = 0; c < 3; ++c) {
        const size_t i = (size_t(y) * 48 + x) * 3 + c;
        const double d = double(images[0].rgb[i]) - images[1].rgb[i];
        diff2[c] += d * d;
      }
    }
  }
  for (int c = 0; c < 3; ++c) {
    const double tessera = 0.5 * (a[c] + b[c]);
    // Variance of one render's mean is mean((a - b)^2) / (2 n); of the two renders' mean, half.
    const double tessera_var = diff2[c] / n / (2.0 * n) / 2.0;
    const double sigma = std::sqrt(tessera_var + mitsuba_se[c] * mitsuba_se[c]);
    const double delta = std::abs(tessera - mitsuba[c]);
    // scripts/mitsuba_sweep.py's rule: within 4 sigma or 1 %.
    EXPECT_TRUE(delta <= 4 * sigma || delta <= 0.01 * mitsuba[c])
        << "channel " << c << ": Tessera " << tessera << ", Mitsuba " << mitsuba[c] << " ("
        << 100 * (tessera - mitsuba[c]) / mitsuba[c] << " %, " << delta / sigma << " sigma)";
  }
}

}  // namespace
}  // namespace tessera
