// `tessera-worker converge`'s pieces: the log-log fit, the error measures, a progressive
// measurement of a white furnace against its closed form, the table and the plot.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include <gtest/gtest.h>
#include <unistd.h>

#include "converge.h"
#include "render/test_statistics.h"

namespace tessera {
namespace {

TEST(LoglogSlope, RecoversAPowerLaw) {
  std::vector<double> x, y;
  for (double v = 1; v <= 1024; v *= 2) {
    x.push_back(v);
    y.push_back(v < 4 ? 100.0 : 3.0 * std::pow(v, -0.5));  // the first two points off the line
  }
  EXPECT_NEAR(loglog_slope(x, y, 4, 1024), -0.5, 1e-12);
  EXPECT_NEAR(loglog_slope(x, y, 16, 64), -0.5, 1e-12);
  EXPECT_LT(loglog_slope(x, y, 1, 1024), -0.5 - 0.1);  // the outliers count when included
  EXPECT_TRUE(std::isnan(loglog_slope(x, y, 5, 7)));   // one point only
  y[5] = 0;
  EXPECT_TRUE(std::isnan(loglog_slope(x, y, 4, 1024)));  // log of zero
}

RgbImage constant(int w, int h, float r, float g, float b) {
  RgbImage im;
  im.width = w;
  im.height = h;
  for (int i = 0; i < w * h; ++i) im.rgb.insert(im.rgb.end(), {r, g, b});
  return im;
}

TEST(ImageError, RmseRelMseAndMean) {
  RgbImage ref = constant(2, 1, 1.0f, 0.0f, 0.5f);
  RgbImage img = ref;
  EXPECT_EQ(image_rmse(img, ref), 0.0);
  img.rgb[0] = 2.0f;  // one of six values off by 1
  EXPECT_NEAR(image_rmse(img, ref), std::sqrt(1.0 / 6.0), 1e-12);
  EXPECT_NEAR(image_relmse(img, ref), 1.0 / (1.0 + kRelMseEpsilon) / 6.0, 1e-12);
  img.rgb[0] = 1.0f;
  img.rgb[1] = 0.1f;  // a black reference pixel: the epsilon keeps it finite
  EXPECT_NEAR(image_relmse(img, ref), 0.01f * 0.01f / kRelMseEpsilon / 6.0 * 100, 1e-6);
  EXPECT_NEAR(image_mean(ref).z, 0.5, 1e-12);
  EXPECT_THROW(image_rmse(img, constant(1, 2, 0, 0, 0)), std::invalid_argument);
}

TEST(Converge, FurnaceAgainstItsClosedForm) {
  // A white furnace's exact image is constant: le / (1 - albedo). The levels are the powers of
  // two, each image the mean of the samples so far; its mean stays within 5 standard errors of
  // the exact value (a channel's RMSE / sqrt(pixels) bounds the standard error of its mean).
  const double albedo = 0.5, le = 0.7, exact = le / (1 - albedo);
  const Scene scene = test::furnace_scene(false, albedo, le);  // the box: noisier than the sphere
  const RgbImage ref = constant(8, 8, float(exact), float(exact), float(exact));
  const ConvergenceResult r = measure_convergence(scene, test::test_job(8, 8, 64), ref, 4);
  ASSERT_EQ(r.rows.size(), 7u);
  for (size_t i = 0; i < r.rows.size(); ++i) {
    const ConvergenceRow& row = r.rows[i];
    EXPECT_EQ(row.spp, 1u << i);
    EXPECT_GT(row.rmse, 0.0);
    EXPECT_TRUE(std::isfinite(row.relmse));
    if (i > 0) {
      EXPECT_GE(row.seconds, r.rows[i - 1].seconds);
    }
    for (int ch = 0; ch < 3; ++ch) {
      // A channel's RMSE is at most sqrt(3) times the RMSE over all channels.
      EXPECT_NEAR(row.mean[ch], exact, test::kSigmas * std::sqrt(3.0) * row.rmse / std::sqrt(64.0))
          << row.spp;
    }
  }
  EXPECT_LT(r.rows.back().rmse, r.rows.front().rmse);
  EXPECT_LT(r.fit.rmse_vs_spp, 0.0);
  EXPECT_EQ(r.fit.spp_from, 4);

  // Table: CSV header plus one line per level, Markdown with the fit.
  const std::string csv = convergence_csv(r);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 8);
  EXPECT_EQ(csv.rfind("spp,seconds,rmse,relmse,mean_r,mean_g,mean_b\n", 0), 0u);
  EXPECT_NE(convergence_markdown(r).find("RMSE ~ spp^"), std::string::npos);

  // Plot: a PNG of the size asked for, not blank.
  const std::filesystem::path png =
      std::filesystem::temp_directory_path() / ("tessera_converge_" + std::to_string(::getpid()) + ".png");
  write_convergence_plot(r, png.string(), 600, 300);
  const RgbImage plot = read_image(png);
  std::filesystem::remove(png);
  EXPECT_EQ(plot.width, 600);
  EXPECT_EQ(plot.height, 300);
  size_t non_white = 0;
  for (float v : plot.rgb) non_white += v < 0.9f;
  EXPECT_GT(non_white, 1000u);
  EXPECT_THROW(write_convergence_plot(r, "/nonexistent-folder/plot.png"), std::runtime_error);
}

TEST(Converge, TooFewLevelsToFitSaySo) {
  const double exact = 0.7 / (1 - 0.5);
  const ConvergenceResult r = measure_convergence(
      test::furnace_scene(true, 0.5, 0.7), test::test_job(4, 4, 4),
      constant(4, 4, float(exact), float(exact), float(exact)), 4);
  ASSERT_EQ(r.rows.size(), 3u);  // 1, 2, 4 spp: one level from 4 on
  EXPECT_TRUE(std::isnan(r.fit.rmse_vs_spp));
  EXPECT_NE(convergence_markdown(r).find("No slope: fewer than two levels from 4 spp on"),
            std::string::npos);
}

TEST(Converge, EachLevelsImageGoesToTheHookWithoutADenoiser) {
  const double exact = 0.7 / (1 - 0.5);
  const RgbImage ref = constant(4, 4, float(exact), float(exact), float(exact));
  ConvergenceHooks hooks;
  std::vector<uint32_t> levels;
  std::vector<double> rmses;
  hooks.on_images = [&](uint32_t spp, const RgbImage& raw, const RgbImage* denoised) {
    levels.push_back(spp);
    rmses.push_back(image_rmse(raw, ref));
    EXPECT_EQ(denoised, nullptr);
  };
  const ConvergenceResult r =
      measure_convergence(test::furnace_scene(true, 0.5, 0.7), test::test_job(4, 4, 8), ref, 4, hooks);
  EXPECT_EQ(levels, (std::vector<uint32_t>{1, 2, 4, 8}));
  ASSERT_EQ(r.rows.size(), 4u);
  for (size_t i = 0; i < r.rows.size(); ++i) {
    EXPECT_EQ(rmses[i], r.rows[i].rmse);
    EXPECT_FALSE(r.rows[i].denoised.has_value());
  }
  EXPECT_EQ(convergence_markdown(r).find("Denoised"), std::string::npos);
  EXPECT_EQ(convergence_csv(r).find("denoised"), std::string::npos);
}

TEST(RawRmseAt, InterpolatesLogLogBetweenTheRowsAround) {
  std::vector<ConvergenceRow> rows(3);
  rows[0].seconds = 1, rows[0].rmse = 0.4;
  rows[1].seconds = 4, rows[1].rmse = 0.2;  // RMSE ~ time^-1/2
  rows[2].seconds = 16, rows[2].rmse = 0.1;
  EXPECT_NEAR(raw_rmse_at(rows, 2), 0.4 / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(raw_rmse_at(rows, 8), 0.2 / std::sqrt(2.0), 1e-12);
  EXPECT_DOUBLE_EQ(raw_rmse_at(rows, 4), 0.2);
  EXPECT_TRUE(std::isnan(raw_rmse_at(rows, 0.5)));  // before the first row
  EXPECT_TRUE(std::isnan(raw_rmse_at(rows, 17)));   // beyond the run
}

TEST(Converge, ReferenceOfAnotherSizeIsAnError) {
  const Scene scene = test::furnace_scene(true, 0.5, 1.0);
  EXPECT_THROW(measure_convergence(scene, test::test_job(8, 8, 4), constant(4, 4, 1, 1, 1), 4),
               std::invalid_argument);
}

}  // namespace
}  // namespace tessera
