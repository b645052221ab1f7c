// The real Open Image Denoise (tessera_oidn_tests, label "slow"): these fail, not skip, where
// the library is missing (scripts/install-deps.sh installs it).
#include "denoise/denoiser.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <stdexcept>

namespace tessera {
namespace {

std::shared_ptr<const OidnLibrary> installed_oidn() {
  return OidnLibrary::load_for_flag("");
}

/// A smooth image (a horizontal ramp from 0.2 to 0.8 in every channel), and the same with
/// noise of standard deviation about 0.1 from a fixed hash.
struct NoisyRamp {
  RgbImage clean, noisy;
};
NoisyRamp noisy_ramp(int width, int height) {
  NoisyRamp r;
  r.clean = {width, height, std::vector<float>(size_t(width) * height * 3)};
  r.noisy = r.clean;
  for (size_t i = 0; i < r.clean.rgb.size(); ++i) {
    const int x = int(i / 3 % size_t(width));
    r.clean.rgb[i] = 0.2f + 0.6f * float(x) / float(width - 1);
    uint32_t h = uint32_t(i) * 2654435761u;
    h ^= h >> 15;
    h *= 2246822519u;
    h ^= h >> 13;
    const float u = float(h & 0xffffff) / float(0x1000000);  // uniform [0, 1)
    r.noisy.rgb[i] = r.clean.rgb[i] + 0.35f * (u - 0.5f);   // sd 0.35/sqrt(12) ~ 0.1
  }
  return r;
}

double rmse(const RgbImage& a, const RgbImage& b) {
  double sum = 0;
  for (size_t i = 0; i < a.rgb.size(); ++i) sum += std::pow(double(a.rgb[i]) - b.rgb[i], 2);
  return std::sqrt(sum / double(a.rgb.size()));
}

TEST(OidnDenoiser, TheInstalledLibraryLoadsAndReportsVersion2) {
  const Denoiser denoiser(installed_oidn());
  EXPECT_EQ(denoiser.version().rfind("2.", 0), 0u) << denoiser.version();
  EXPECT_NE(denoiser.description(false).find("colour only"), std::string::npos);
  EXPECT_NE(denoiser.description(true).find("albedo and normal"), std::string::npos);
}

TEST(OidnDenoiser, ColourOnlyRemovesMostOfTheNoise) {
  const Denoiser denoiser(installed_oidn(), 2);
  const NoisyRamp r = noisy_ramp(128, 96);
  const RgbImage out = denoiser.denoise(r.noisy);
  ASSERT_EQ(out.width, 128);
  ASSERT_EQ(out.height, 96);
  EXPECT_LT(rmse(out, r.clean), rmse(r.noisy, r.clean) / 3) << rmse(r.noisy, r.clean);
}

TEST(OidnDenoiser, GuidedByAlbedoAndNormal) {
  const Denoiser denoiser(installed_oidn(), 2);
  const NoisyRamp r = noisy_ramp(128, 96);
  const RgbImage albedo{128, 96, std::vector<float>(r.clean.rgb.size(), 0.5f)};
  RgbImage normal{128, 96, std::vector<float>(r.clean.rgb.size(), 0.0f)};
  for (size_t i = 2; i < normal.rgb.size(); i += 3) normal.rgb[i] = 1.0f;
  const RgbImage out = denoiser.denoise(r.noisy, {&albedo, &normal});
  EXPECT_LT(rmse(out, r.clean), rmse(r.noisy, r.clean) / 3) << rmse(r.noisy, r.clean);
}

TEST(OidnDenoiser, GuidesOfAnotherSizeAreRefused) {
  const Denoiser denoiser(installed_oidn(), 2);
  const NoisyRamp r = noisy_ramp(16, 16);
  const RgbImage small{8, 8, std::vector<float>(8 * 8 * 3, 0.5f)};
  EXPECT_THROW(denoiser.denoise(r.noisy, {&small, &small}), std::runtime_error);
}

}  // namespace
}  // namespace tessera
