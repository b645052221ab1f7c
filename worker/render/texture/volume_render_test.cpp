// The volume texture scene (tests/data/mitsuba/volume/scene.xml: grids on a floor, a sphere and
// two instances of one group, constants on a rough metal) rendered by Tessera against Mitsuba
// 3.9.1's image mean (mitsuba_volume_scene.py wrote mitsuba_volume_scene.txt).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "accum/film.h"
#include "job/job_options.h"
#include "image/image_output.h"
#include "local_render.h"
#include "scene/scene_loader.h"

namespace tessera {
namespace {

std::array<double, 3> image_mean(const RgbImage& image) {
  std::array<double, 3> sum{0, 0, 0};
  const size_t pixels = image.rgb.size() / 3;
  for (size_t i = 0; i < pixels; ++i) {
    for (int c = 0; c < 3; ++c) sum[c] += image.rgb[i * 3 + c];
  }
  for (double& v : sum) v /= double(pixels);
  return sum;
}

TEST(VolumeRender, SceneMatchesMitsuba) {
  const std::string dir = std::string(TESSERA_SOURCE_DIR);
  std::ifstream in(dir + "/worker/render/texture/mitsuba_volume_scene.txt");
  ASSERT_TRUE(in) << "cannot read mitsuba_volume_scene.txt";
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

  const Scene scene = load_scene_file(dir + "/tests/data/mitsuba/volume/scene.xml");
  ASSERT_EQ(scene.textures.size(), 5u);
  // Two seeds: their difference per pixel gives the noise of Tessera's mean (as
  // scripts/mitsuba_sweep.py estimates it).
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
    for (const Accumulation& t : result.tiles) {
      EXPECT_EQ(t.nan_dropped + t.inf_dropped, 0u);
    }
    images[seed] = resolve_image(options.width, options.height, result.tiles);
  }
  const std::array<double, 3> a = image_mean(images[0]), b = image_mean(images[1]);
  const size_t n = images[0].rgb.size() / 3;
  std::array<double, 3> diff2{0, 0, 0};
  for (size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) {
      const double d = double(images[0].rgb[i * 3 + c]) - images[1].rgb[i * 3 + c];
      diff2[c] += d * d;
    }
  }
  for (int c = 0; c < 3; ++c) {
    const double tessera = 0.5 * (a[c] + b[c]);
    // Variance of one render's mean is mean((a - b)^2) / (2 n); of the two renders' mean, half.
    const double tessera_var = diff2[c] / double(n) / (2.0 * double(n)) / 2.0;
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
