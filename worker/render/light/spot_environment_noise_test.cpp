// A dim constant environment beside narrow spot lights
// (tests/data/mitsuba/spot_sphere_constant.xml, mitsuba-data's emitter_spot_no_texture at
// 32 x 32): the light picker must keep giving the spots the direct-light sample where they
// shine, so the spot-lit pixels are hardly noisier with the environment than without it, and
// the image keeps its mean.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <iostream>
#include <string>
#include <vector>

#include "accum/film.h"
#include "job/job_options.h"
#include "local_render.h"
#include "scene/scene.h"
#include "scene/loader/scene_loader.h"

namespace tessera {
namespace {

constexpr int kSeeds = 6;
constexpr int kSpp = 8;

/// The scene's image for each seed.
std::vector<RgbImage> render_seeds(const Scene& scene) {
  std::vector<RgbImage> images;
  for (int seed = 0; seed < kSeeds; ++seed) {
    JobOverrides overrides;
    overrides.spp = kSpp;
    overrides.seed = uint64_t(seed);
    const JobOptions options = resolve_job_options(scene, overrides);
    const LocalRenderResult result = render_job(scene, options);
    for (const Accumulation& t : result.tiles) EXPECT_EQ(t.nan_dropped + t.inf_dropped, 0u);
    images.push_back(resolve_image(options.width, options.height, result.tiles));
  }
  return images;
}

/// Per-pixel, per-channel mean over the seeds.
std::vector<double> mean_of(const std::vector<RgbImage>& images) {
  std::vector<double> mean(images[0].rgb.size(), 0.0);
  for (const RgbImage& image : images) {
    for (size_t i = 0; i < mean.size(); ++i) {
      mean[i] += double(image.rgb[i]) / double(images.size());
    }
  }
  return mean;
}

/// The sum over the pixels in `mask` and their channels of the variance over the seeds.
double variance_over(const std::vector<RgbImage>& images, const std::vector<bool>& mask) {
  const std::vector<double> mean = mean_of(images);
  double sum = 0;
  for (size_t i = 0; i < mean.size(); ++i) {
    if (!mask[i / 3]) continue;
    for (const RgbImage& image : images) {
      const double d = double(image.rgb[i]) - mean[i];
      sum += d * d / double(images.size() - 1);
    }
  }
  return sum;
}

TEST(SpotEnvironmentNoise, ADimEnvironmentHardlyAddsNoiseWhereTheSpotsShine) {
  const Scene with_environment = load_scene_file(std::string(TESSERA_SOURCE_DIR) +
                                                 "/tests/data/mitsuba/spot_sphere_constant.xml");
  Scene without_environment = with_environment;
  std::erase_if(without_environment.lights,
                [](const Light& l) { return l.kind == LightKind::constant; });
  ASSERT_EQ(without_environment.lights.size() + 1, with_environment.lights.size());

  const std::vector<RgbImage> with = render_seeds(with_environment);
  const std::vector<RgbImage> without = render_seeds(without_environment);
  // The spot-lit pixels: red or blue well above what the environment alone gives (about 0.03).
  const std::vector<double> lit = mean_of(without);
  std::vector<bool> mask(lit.size() / 3);
  int count = 0;
  for (size_t p = 0; p < mask.size(); ++p) {
    mask[p] = std::max(lit[3 * p], lit[3 * p + 2]) > 0.2;
    count += mask[p];
  }
  ASSERT_GT(count, 30);
  const double factor = variance_over(with, mask) / variance_over(without, mask);
  std::cout << "spot-lit pixels: " << count << ", variance with / without the environment: "
            << factor << "\n";
  // Weighed by power, the environment took 84 % of the direct-light samples on the sphere and
  // made these pixels several times noisier.
  EXPECT_LT(factor, 1.5);

  // The environment only adds light: the mean over the lit pixels grows by about what it gives
  // a diffuse surface (0.1 times the albedo, and less where the sphere hides it), never shrinks.
  const std::vector<double> lit_with = mean_of(with);
  double added = 0;
  for (size_t i = 0; i < lit.size(); ++i) {
    if (mask[i / 3]) added += (lit_with[i] - lit[i]) / (3.0 * count);
  }
  EXPECT_GT(added, 0.005);
  EXPECT_LT(added, 0.06);
}

}  // namespace
}  // namespace tessera
