// Stopping rules: the per-tile error estimate, the rule's verdicts, and how options resolve
// (presets, exclusivity, the one-line errors naming the flag).
#include "job/stopping_rule.h"

#include <gtest/gtest.h>

#include <cmath>

#include "accum/film.h"
#include "job/job_options.h"
#include "job/tile_summary.h"

namespace tessera {
namespace {

/// A 2x1 tile where every pixel saw `n` samples of luminance alternating between lo and hi
/// (grey radiance, so luminance = the value: 0.2126 + 0.7152 + 0.0722 = 1).
Accumulation two_valued(uint32_t n, double lo, double hi) {
  Accumulation acc(TileRect{0, 0, 2, 1});
  for (size_t p = 0; p < acc.pixels(); ++p) {
    for (uint32_t i = 0; i < n; ++i) {
      const double v = i % 2 == 0 ? lo : hi;
      for (int c = 0; c < 3; ++c) acc.rgb[p * 3 + c] += v;
      acc.lum2[p] += v * v;
    }
    acc.count[p] = n;
  }
  return acc;
}

TEST(RelativeError, MatchesTheFormulaOnOneTile) {
  // n samples alternating 1 and 3: mean 2, unbiased sample variance n/(n-1), variance of the
  // mean 1/(n-1); relative error sqrt(1/(n-1)) / 2.
  for (uint32_t n : {2u, 16u, 64u}) {
    const Accumulation acc = two_valued(n, 1.0, 3.0);
    EXPECT_NEAR(estimate_relative_error(acc), std::sqrt(1.0 / (n - 1)) / 2.0, 1e-12) << n;
    // The one-tile form is the many-tile form over one tile.
    EXPECT_EQ(estimate_relative_error(acc),
              estimate_relative_error(std::vector<Accumulation>{acc}));
  }
}

TEST(RelativeError, DarkTilesAreMeasuredAgainstAFloor) {
  // Mean luminance 1e-6 is below the 1e-4 floor: the error is absolute noise / 1e-4.
  const Accumulation acc = two_valued(2, 0.0, 2e-6);
  const double abs_noise = std::sqrt(1e-12);  // variance of the mean of 2 samples of {0, 2e-6}
  EXPECT_NEAR(estimate_relative_error(acc), abs_noise / 1e-4, 1e-12);
  // A black tile (no variance) has error 0: it is converged.
  EXPECT_EQ(estimate_relative_error(two_valued(16, 0.0, 0.0)), 0.0);
}

TEST(JudgeTile, NoiseRuleWaitsFor16SppThenComparesWithTheTarget) {
  const Accumulation smooth = two_valued(16, 1.0, 1.001);  // tiny error
  // 8 spp merged: under the minimum, not judged yet.
  EXPECT_FALSE(judge_tile(StopRule::noise, 0.02, two_valued(8, 1.0, 1.001), 1, 8, 8).finished);
  const TileVerdict met = judge_tile(StopRule::noise, 0.02, smooth, 1, 8, 16);
  EXPECT_TRUE(met.finished);
  EXPECT_EQ(met.reason, StopReason::noise_target);
  EXPECT_EQ(met.relative_error, estimate_relative_error(smooth));
  const Accumulation noisy = two_valued(16, 0.0, 10.0);  // error ~0.26
  EXPECT_FALSE(judge_tile(StopRule::noise, 0.02, noisy, 1, 8, 16).finished);
  const TileVerdict capped = judge_tile(StopRule::noise, 0.02, noisy, 8, 8, 128);
  EXPECT_TRUE(capped.finished);
  EXPECT_EQ(capped.reason, StopReason::max_spp);
  // Met and capped at once: the target is the better answer.
  EXPECT_EQ(judge_tile(StopRule::noise, 0.02, smooth, 8, 8, 128).reason, StopReason::noise_target);
}

TEST(JudgeTile, SppAndTimeRulesFinishOnlyAtTheirLastBatch) {
  const Accumulation smooth = two_valued(16, 1.0, 1.0);
  EXPECT_FALSE(judge_tile(StopRule::spp, 0, smooth, 3, 4, 48).finished);
  EXPECT_EQ(judge_tile(StopRule::spp, 0, smooth, 4, 4, 64).reason, StopReason::spp_reached);
  EXPECT_FALSE(judge_tile(StopRule::time, 0, smooth, 3, 4, 48).finished);
  EXPECT_EQ(judge_tile(StopRule::time, 0, smooth, 4, 4, 64).reason, StopReason::max_spp);
}

Scene scene() {
  Scene s;
  s.film.width = 64;
  s.film.height = 32;
  s.render.spp = 32;
  return s;
}

TEST(ResolveJobOptions, AValueFromTheSceneIsBlamedOnTheScene) {
  Scene s = scene();
  s.render.spp = int64_t{1} << 32;
  s.film.width = 0;
  auto error = [](const Scene& sc, const JobOverrides& o) -> std::string {
    try {
      resolve_job_options(sc, o);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(error(s, {}),
            "the scene's width (film.width; --width overrides it): must be in [1, 32768] (got 0)");
  s.film.width = 64;
  EXPECT_EQ(error(s, {}), "the scene's spp (render.spp; --spp overrides it): must be in [1, "
                          "2147483648] (got 4294967296)");
  JobOverrides o;
  o.spp = 0;
  EXPECT_EQ(error(s, o), "--spp: must be in [1, 2147483648] (got 0)");
}

std::string resolve_error(const JobOverrides& o) {
  try {
    resolve_job_options(scene(), o);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(ResolveStoppingRule, NoiseJobsPlanUpToTheCapIn16SppBatches) {
  JobOverrides o;
  o.noise = 0.02;
  const JobOptions job = resolve_job_options(scene(), o);
  EXPECT_EQ(job.rule, StopRule::noise);
  EXPECT_EQ(job.noise_target, 0.02);
  EXPECT_EQ(job.spp, kDefaultMaxSpp);
  EXPECT_EQ(job.batch_spp, kNoiseBatchSpp);
  EXPECT_EQ(job.batch_kind, BatchKind::fixed);
  o.max_spp = 8;
  EXPECT_EQ(resolve_job_options(scene(), o).batch_spp, 8u);  // never more than the cap
  o.max_spp = 1024;
  o.batch_spp = 32;
  EXPECT_EQ(resolve_job_options(scene(), o).batch_spp, 32u);  // the user's batch wins
}

TEST(ResolveStoppingRule, TimeJobsKeepABudgetAndACap) {
  JobOverrides o;
  o.time_s = 10;
  const JobOptions job = resolve_job_options(scene(), o);
  EXPECT_EQ(job.rule, StopRule::time);
  EXPECT_EQ(job.time_budget_s, 10.0);
  EXPECT_EQ(job.spp, kDefaultMaxSpp);
  EXPECT_EQ(job.batch_spp, default_batch_spp(64, 64, 32, kDefaultMaxSpp));
  EXPECT_EQ(job.batch_kind, BatchKind::progressive);  // 1 spp first: every tile early
}

TEST(ResolveStoppingRule, PresetsArePlainRules) {
  JobOverrides o;
  o.preset = "final";
  const JobOptions final_job = resolve_job_options(scene(), o);
  EXPECT_EQ(final_job.rule, StopRule::noise);
  EXPECT_EQ(final_job.noise_target, 0.02);
  EXPECT_EQ(final_job.spp, 4096u);
  o.preset = "draft";
  const JobOptions draft = resolve_job_options(scene(), o);
  EXPECT_EQ(draft.rule, StopRule::spp);
  EXPECT_EQ(draft.spp, 16u);
  o.preset = "preview";
  o.max_spp = 100;  // a noise preset's cap may be changed
  EXPECT_EQ(resolve_job_options(scene(), o).spp, 100u);
  for (const QualityPreset& p : quality_presets()) EXPECT_EQ(find_preset(p.name)->name, p.name);
}

TEST(ResolveStoppingRule, BadValuesAndClashesNameTheFlag) {
  JobOverrides o;
  o.noise = -1;
  EXPECT_EQ(resolve_error(o), "--noise: must be > 0 (got -1)");
  o.noise = std::nan("");
  EXPECT_EQ(resolve_error(o), "--noise: must be > 0 (got nan)");
  o = {};
  o.time_s = 0;
  EXPECT_EQ(resolve_error(o), "--time: must be > 0 (got 0)");
  o = {};
  o.noise = 0.1;
  o.max_spp = 0;
  EXPECT_EQ(resolve_error(o), "--max-spp: must be in [1, 2147483648] (got 0)");
  o = {};
  o.spp = 16;
  o.noise = 0.1;
  EXPECT_EQ(resolve_error(o), "--spp and --noise are mutually exclusive: give one stopping rule");
  o = {};
  o.time_s = 5;
  o.preset = "final";
  EXPECT_EQ(resolve_error(o), "--time and --preset are mutually exclusive: give one stopping rule");
  o = {};
  o.spp = 16;
  o.max_spp = 64;
  EXPECT_EQ(resolve_error(o), "--max-spp: only with --noise, --time or a noise preset");
  o = {};
  o.preset = "best";
  EXPECT_EQ(resolve_error(o),
            "--preset: unknown preset \"best\" (use draft, preview, final, reference)");
  o.preset = "draft";
  o.max_spp = 64;
  EXPECT_EQ(resolve_error(o),
            "--max-spp: only with --noise, --time or a noise preset (draft is 16 spp)");
}

TEST(TileSummary, SummarisesAndSpreadsPerTileSpp) {
  const TileSummary s = summarize_tiles({16, 48, 32}, {0.01, 0.03, 0.02});
  EXPECT_EQ(s.spp_min, 16u);
  EXPECT_EQ(s.spp_max, 48u);
  EXPECT_EQ(s.spp_mean, 32.0);
  EXPECT_EQ(s.error_max, 0.03);
  EXPECT_NEAR(s.error_mean, 0.02, 1e-15);
  const std::vector<float> channel = spp_channel(3, 2, {{0, 0, 2, 2}, {2, 0, 3, 2}}, {16, 48});
  EXPECT_EQ(channel, (std::vector<float>{16, 16, 48, 16, 16, 48}));
}

}  // namespace
}  // namespace tessera
