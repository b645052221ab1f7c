// The server's denoiser with the real Open Image Denoise (tessera_server_oidn_tests, label
// "slow", as core/denoise's tests: they fail, not skip, where the library is missing): one
// denoise at a time, its working set reserved in the memory budget while it runs.
#include "job_denoise.h"

#include <gtest/gtest.h>

#include <thread>
#include <vector>

namespace tessera::server {
namespace {

std::vector<std::string> installed_candidates() {
  return oidn_library_candidates_for_flag("");
}

/// A flat grey image with a little deterministic noise, and flat guides.
RgbImage noisy_grey(int width, int height) {
  RgbImage image{width, height, std::vector<float>(size_t(width) * size_t(height) * 3)};
  for (size_t i = 0; i < image.rgb.size(); ++i) {
    image.rgb[i] = 0.5f + 0.1f * float(int((i * 2654435761u) >> 28) - 8) / 8.0f;
  }
  return image;
}

TEST(JobDenoise, DenoisesWithGuidesNamingTheDenoiser) {
  SubmitBudget budget(uint64_t(1) << 30);
  JobDenoise denoise(installed_candidates(), &budget);
  ASSERT_EQ(denoise.unavailable(), "");
  EXPECT_NO_THROW(denoise.check_submit(32, 24));
  const RgbImage color = noisy_grey(32, 24);
  GuideImages guides{{32, 24, std::vector<float>(32 * 24 * 3, 0.5f)},
                     {32, 24, std::vector<float>(32 * 24 * 3, 0.0f)}};
  for (size_t i = 2; i < guides.normal.rgb.size(); i += 3) guides.normal.rgb[i] = 1.0f;
  const JobDenoise::Denoised out =
      denoise.denoise("job 1's denoise", 32, 24, [&] { return JobDenoise::Input{color, guides}; });
  EXPECT_EQ(out.image.width, 32);
  EXPECT_EQ(out.image.rgb.size(), color.rgb.size());
  EXPECT_NE(out.denoiser.find("Open Image Denoise"), std::string::npos) << out.denoiser;
  EXPECT_NE(out.denoiser.find("albedo and normal"), std::string::npos) << out.denoiser;
  const auto colour_only = [&] { return JobDenoise::Input{color, {}}; };
  EXPECT_NE(denoise.denoise("job 2's denoise", 32, 24, colour_only).denoiser.find("colour only"),
            std::string::npos);
  const SubmitBudget::Counters c = budget.counters();
  EXPECT_EQ(c.reserved_bytes, 0u);  // released once done
  EXPECT_EQ(c.peak_reserved_bytes, JobDenoise::working_set_bytes(32, 24));
}

TEST(JobDenoise, RunsOneDenoiseAtATime) {
  // Room for four at once in the budget: the peak shows one.
  SubmitBudget budget(JobDenoise::working_set_bytes(64, 64) * 4);
  JobDenoise denoise(installed_candidates(), &budget);
  const RgbImage color = noisy_grey(64, 64);
  std::vector<std::thread> threads;
  for (int i = 0; i < 3; ++i) {
    threads.emplace_back([&, i] {
      denoise.denoise("job " + std::to_string(i), 64, 64,
                      [&] { return JobDenoise::Input{color, {}}; });
    });
  }
  for (std::thread& t : threads) t.join();
  EXPECT_EQ(budget.counters().admitted, 3u);
  EXPECT_EQ(budget.counters().peak_reserved_bytes, JobDenoise::working_set_bytes(64, 64));
}

}  // namespace
}  // namespace tessera::server
