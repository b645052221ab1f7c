// Long statistical renders (label "slow"): the Cornell box's error against Mitsuba's reference
// falls like Monte Carlo's or faster, with no drift of the image mean; a 4x4 white furnace at
// 1,000,000 spp equals its closed form. docs/accuracy.md lists them.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "converge.h"
#include "image_compare.h"
#include "render/test_statistics.h"
#include "scene/loader/scene_loader.h"

namespace tessera {
namespace {

const std::string kSource = TESSERA_SOURCE_DIR;

TEST(Convergence, CornellRmseFallsWithSlopeHalfOrSteeperAndTheMeanDoesNotDrift) {
  // The Cornell box at depth 8 against ref_depth8.exr, rendered at 128x128 against the reference
  // averaged over 2x2 blocks (the box filter makes a 128x128 pixel exactly the mean of its four
  // 256x256 pixels; a quarter of the work). Levels 1, 2, 4, ..., 1024 spp, each the prefix of the
  // same sample sequence; the slope is fitted from 4 to 1024 spp.
  const Scene scene = load_scene_file(kSource + "/scenes/cornell.json");
  const RgbImage ref =
      test::downsample(read_image(kSource + "/tests/data/reference/cbox/ref_depth8.exr"), 2);
  JobOverrides o;
  o.width = o.height = 128;
  o.spp = 1024;
  o.max_depth = 8;
  o.seed = 3;
  const ConvergenceResult result = measure_convergence(scene, resolve_job_options(scene, o), ref, 4);
  std::fputs(convergence_markdown(result).c_str(), stdout);
  ASSERT_EQ(result.rows.size(), 11u);

  // Monte Carlo's RMSE falls as spp^-1/2; Tessera's stratified samples do better. The reference's
  // own noise makes the measured curve flatter at high spp, never steeper.
  EXPECT_LE(result.fit.rmse_vs_spp, -0.5 + 0.08);
  for (size_t i = 1; i < result.rows.size(); ++i) {
    EXPECT_LT(result.rows[i].rmse, result.rows[i - 1].rmse) << result.rows[i].spp << " spp";
  }

  // No drift: at every level the image mean is within 5 standard errors of the reference's
  // mean. Pixels are independent (each has its own scrambling), so the standard error of the
  // image mean of a channel is at most that channel's RMSE / sqrt(pixels), and a channel's RMSE
  // is at most sqrt(3) times the RMSE over all three (the RMSE includes the reference's own
  // noise, which makes this conservative).
  const double pixels = double(ref.width) * double(ref.height);
  for (const ConvergenceRow& row : result.rows) {
    const double tol = test::kSigmas * std::sqrt(3.0) * row.rmse / std::sqrt(pixels);
    for (int ch = 0; ch < 3; ++ch) {
      EXPECT_NEAR(row.mean[ch], result.reference_mean[ch], tol)
          << row.spp << " spp, channel " << ch;
    }
  }
}

TEST(Extremes, FurnaceMillionSppMatchesTheClosedFormWithoutDrift) {
  // extremes_test.cpp's FurnaceAccumulatedOverManyBatchesHasNoDrift at 1,000,000 spp: 4x4
  // pixels, 245 batches of 4096 samples (the last one partial) merged in order. A float
  // accumulator would drift by ~1e6 * 6e-8 = 6 % here; the double sums must stay within
  // 5 standard errors (~2e-4 relative) of le / (1 - albedo).
  const double albedo = 0.5, le = 0.7;
  const uint32_t spp = 1000000, batch = 4096;
  const Renderer renderer(test::furnace_scene(true, albedo, le), test::test_job(4, 4, spp));
  const Accumulation acc = test::render_batches(renderer, spp, batch);
  const double expected = test::furnace_expected(albedo, le, -1);
  const test::Estimate e = test::mean_luminance(acc);
  std::printf("furnace, %u spp: mean %.8f, expected %.8f, SE %.2e\n", spp, e.mean, expected, e.se);
  for (uint32_t n : acc.count) EXPECT_EQ(n, spp);
  EXPECT_GT(e.se, 0.0);
  EXPECT_NEAR(e.mean, expected, test::tolerance(e, expected));
  for (size_t i = 0; i < acc.pixels(); ++i) {
    const test::Estimate p = test::pixel_luminance(acc, i);
    EXPECT_NEAR(p.mean, expected, test::tolerance(p, expected)) << "pixel " << i;
  }
  EXPECT_TRUE(test::all_finite(acc));
}

}  // namespace
}  // namespace tessera
