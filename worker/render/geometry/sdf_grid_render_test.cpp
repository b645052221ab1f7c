// SDF grids through the whole renderer: the torus of Mitsuba's sdfgrid docs scenes in a
// shapegroup placed by an instance (tests/data/mitsuba/sdfgrid/torus_*.xml, smooth and analytic
// normals) read by the importer and rendered as `tessera-worker render` renders it matches
// Mitsuba 3.9.1's image mean (mitsuba_sdfgrid_scene.py -> mitsuba_sdfgrid_scene.txt), and the
// packet (wavefront) integrator gives the same bits as the scalar one.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <cstring>

#include <tbb/task_arena.h>

#include "accum/film.h"
#include "job/job_options.h"
#include "local_render.h"
#include "render/integrator.h"
#include "render/renderer.h"
#include "scene/scene_loader.h"

namespace tessera {
namespace {

/// Per channel: the mean of `image` without a 2-pixel border (as mitsuba_sdfgrid_scene.py
/// takes Mitsuba's).
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

struct Reference {
  std::array<double, 3> mean{}, se{};
};

std::map<std::string, Reference> read_references(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in) << "cannot read " << path;
  std::map<std::string, Reference> out;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream row(line);
    std::string scene, channel;
    double mean = 0, se = 0;
    EXPECT_TRUE(row >> scene >> channel >> mean >> se) << line;
    const int c = channel == "r" ? 0 : channel == "g" ? 1 : 2;
    out[scene].mean[c] = mean;
    out[scene].se[c] = se;
  }
  return out;
}

TEST(SdfGridRender, TorusScenesMatchMitsuba) {
  const std::string dir = std::string(TESSERA_SOURCE_DIR);
  const auto references = read_references(dir + "/worker/render/geometry/mitsuba_sdfgrid_scene.txt");
  ASSERT_EQ(references.size(), 2u);
  for (const auto& [name, mitsuba] : references) {
    const Scene scene = load_scene_file(dir + "/tests/data/mitsuba/sdfgrid/" + name + ".xml");
    // Two seeds: their difference per pixel gives the noise of Tessera's mean.
    const int kSpp = 32;
    std::array<RgbImage, 2> images;
    for (int seed = 0; seed < 2; ++seed) {
      JobOverrides overrides;
      overrides.spp = kSpp;
      overrides.seed = uint64_t(seed);
      const JobOptions options = resolve_job_options(scene, overrides);
      ASSERT_EQ(options.width, 64);
      ASSERT_EQ(options.height, 48);
      const LocalRenderResult result = render_job(scene, options);
      for (const Accumulation& t : result.tiles) EXPECT_EQ(t.nan_dropped + t.inf_dropped, 0u);
      images[seed] = resolve_image(options.width, options.height, result.tiles);
    }
    const std::array<double, 3> a = inner_mean(images[0]), b = inner_mean(images[1]);
    std::array<double, 3> diff2{0, 0, 0};
    int n = 0;
    for (int y = 2; y < 46; ++y) {
      for (int x = 2; x < 62; ++x, ++n) {
        for (int c = 0; c < 3; ++c) {
          const size_t i = (size_t(y) * 64 + x) * 3 + c;
          const double d = double(images[0].rgb[i]) - images[1].rgb[i];
          diff2[c] += d * d;
        }
      }
    }
    for (int c = 0; c < 3; ++c) {
      const double tessera = 0.5 * (a[c] + b[c]);
      const double tessera_var = diff2[c] / n / (2.0 * n) / 2.0;
      const double sigma = std::sqrt(tessera_var + mitsuba.se[c] * mitsuba.se[c]);
      const double delta = std::abs(tessera - mitsuba.mean[c]);
      // scripts/mitsuba_sweep.py's rule: within 4 sigma or 1 %.
      EXPECT_TRUE(delta <= 4 * sigma || delta <= 0.01 * mitsuba.mean[c])
          << name << " channel " << c << ": Tessera " << tessera << ", Mitsuba " << mitsuba.mean[c] << " ("
          << 100 * (tessera - mitsuba.mean[c]) / mitsuba.mean[c] << " %, " << delta / sigma << " sigma)";
    }
  }
}

/// The wavefront integrator traces packets: its SDF hits (found through Embree's instance
/// transform) must give the scalar integrator's bits, with 1 and 2 threads.
TEST(SdfGridRender, WavefrontGivesTheScalarBits) {
  const std::string dir = std::string(TESSERA_SOURCE_DIR);
  for (const char* name : {"torus_smooth", "torus_analytic"}) {
    const Scene scene = load_scene_file(dir + "/tests/data/mitsuba/sdfgrid/" + name + ".xml");
    JobOverrides overrides;
    overrides.width = 32;
    overrides.height = 24;
    overrides.spp = 4;
    overrides.seed = 11;
    const JobOptions options = resolve_job_options(scene, overrides);
    const Renderer scalar(scene, options, {}, IntegratorKind::scalar);
    const Renderer wavefront(scene, options, {}, IntegratorKind::wavefront);
    ASSERT_EQ(wavefront.integrator(), IntegratorKind::wavefront);
    const TileRect tile{0, 0, 32, 24};
    const Accumulation expected = scalar.render(tile, 0, 4, nullptr);
    for (int threads : {1, 2}) {
      Accumulation got;
      tbb::task_arena(threads).execute([&] { got = wavefront.render(tile, 0, 4, nullptr); });
      EXPECT_EQ(got.nan_dropped + got.inf_dropped, 0u);
      ASSERT_EQ(got.rgb.size(), expected.rgb.size());
      EXPECT_EQ(std::memcmp(got.rgb.data(), expected.rgb.data(), got.rgb.size() * sizeof(got.rgb[0])), 0)
          << name << ", " << threads << " threads";
    }
  }
}

}  // namespace
}  // namespace tessera
