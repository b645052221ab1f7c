// `tessera-worker render --denoise` end to end, with the real Open Image Denoise (label "slow").
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <unistd.h>
#include <algorithm>

#include <gtest/gtest.h>

#include "denoise/denoiser.h"
#include "image/image_output.h"
#include "image_compare.h"

namespace tessera {
namespace {

const std::string kSource = TESSERA_SOURCE_DIR;

/// A fresh folder for one test's files.
std::filesystem::path denoise_test_dir(const std::string& name) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("tessera_denoise_test_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

/// Runs tessera-worker render on the Cornell box at `spp` with `flags`; returns its status.
int render_cornell(int spp, const std::string& flags, const std::filesystem::path& out) {
  const std::string command = std::string(TESSERA_WORKER) + " render " + kSource +
                              "/scenes/cornell.json -q --spp " + std::to_string(spp) + " " + flags +
                              " -o " + out.string();
  return std::system(command.c_str());
}

/// RMSE against `ref` over the pixels where every channel of `ref` is at most 1 (`lit` false)
/// or where one is above (`lit` true: the light).
double masked_rmse(const RgbImage& img, const RgbImage& ref, bool lit) {
  double sum = 0;
  size_t n = 0;
  for (size_t p = 0; p < ref.rgb.size() / 3; ++p) {
    const float* r = &ref.rgb[p * 3];
    if ((std::max({r[0], r[1], r[2]}) > 1.0f) != lit) continue;
    for (int c = 0; c < 3; ++c) sum += std::pow(double(img.rgb[p * 3 + c]) - r[c], 2);
    n += 3;
  }
  return std::sqrt(sum / double(n));
}

std::string file_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

bool same_bits(const RgbImage& a, const RgbImage& b) {
  return a.rgb.size() == b.rgb.size() &&
         std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

// The figure of docs/accuracy.md ("Denoising"): scenes/cornell.json renders unbounded depth,
// as ref_unbounded.exr was made.
TEST(CornellDenoise, EightSamplesDenoisedAreWithinAThirdOfTheRawError) {
  const std::filesystem::path dir = denoise_test_dir("cornell");
  ASSERT_EQ(render_cornell(8, "", dir / "raw.exr"), 0);
  ASSERT_EQ(render_cornell(8, "--denoise", dir / "d.exr"), 0);
  ASSERT_EQ(render_cornell(8, "--denoise --guides", dir / "g.exr"), 0);
  const RgbImage ref = read_image(kSource + "/tests/data/reference/cbox/ref_unbounded.exr");
  const RgbImage raw = read_image(dir / "raw.exr");
  const RgbImage denoised = read_image(dir / "d.denoised.exr");
  // The raw image's R, G, B bits do not depend on the flags; --guides adds its channels.
  EXPECT_TRUE(same_bits(raw, read_image(dir / "d.exr")));
  EXPECT_TRUE(same_bits(raw, read_image(dir / "g.exr")));
  EXPECT_LT(test::rmse(denoised, read_image(dir / "g.denoised.exr")), 1e-4);
  const std::string guided_raw = file_bytes(dir / "g.exr");
  for (const char* channel : {"albedo.R", "albedo.G", "albedo.B", "N.X", "N.Y", "N.Z"}) {
    EXPECT_NE(guided_raw.find(channel), std::string::npos) << channel;
    EXPECT_EQ(file_bytes(dir / "d.exr").find(channel), std::string::npos) << channel;
  }
  // Colour alone, for comparison: OIDN on the raw image without guides.
  const Denoiser colour_only(OidnLibrary::load_for_flag(""));
  const RgbImage colour_denoised = colour_only.denoise(raw);

  const double raw_error = masked_rmse(raw, ref, false), error = masked_rmse(denoised, ref, false);
  std::printf("8 spp, pixels where the reference <= 1: RMSE raw %.5f, denoised %.5f (%.1fx lower; "
              "colour only %.5f); on the light: raw %.4f, denoised %.4f (colour only %.4f)\n",
              raw_error, error, raw_error / error, masked_rmse(colour_denoised, ref, false),
              masked_rmse(raw, ref, true), masked_rmse(denoised, ref, true),
              masked_rmse(colour_denoised, ref, true));
  EXPECT_LE(error, raw_error / 3);
  EXPECT_LE(masked_rmse(colour_denoised, ref, false), raw_error / 3);
  // The denoised file names the denoiser and its version.
  EXPECT_NE(file_bytes(dir / "d.denoised.exr").find("Intel Open Image Denoise 2."), std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST(CornellDenoise, APngOutputGetsADenoisedPngAndExr) {
  const std::filesystem::path dir = denoise_test_dir("png");
  ASSERT_EQ(render_cornell(1, "--denoise --width 64 --height 64", dir / "a.png"), 0);
  EXPECT_TRUE(std::filesystem::exists(dir / "a.png"));
  EXPECT_TRUE(std::filesystem::exists(dir / "a.denoised.png"));
  EXPECT_TRUE(std::filesystem::exists(dir / "a.denoised.exr"));
  std::filesystem::remove_all(dir);
}

// `converge --denoise`: each level measured raw and denoised, the denoised one at its own time
// (guides and denoising included), both images kept under --images.
TEST(CornellDenoise, ConvergeMeasuresTheDenoisedImageBesideTheRawOne) {
  const std::filesystem::path dir = denoise_test_dir("converge");
  const std::string command = std::string(TESSERA_WORKER) + " converge " + kSource +
                              "/scenes/cornell.json --reference " + kSource +
                              "/tests/data/reference/cbox/ref_unbounded.exr --spp 8 --denoise -q --csv " +
                              (dir / "c.csv").string() + " --images " + dir.string() + " > " +
                              (dir / "c.md").string();
  ASSERT_EQ(std::system(command.c_str()), 0);
  std::ifstream csv(dir / "c.csv");
  std::string header, line;
  std::getline(csv, header);
  EXPECT_EQ(header, "spp,seconds,rmse,relmse,mean_r,mean_g,mean_b,denoised_seconds,denoised_rmse,"
                    "denoised_relmse,denoised_mean_r,denoised_mean_g,denoised_mean_b");
  int rows = 0;
  double spp = 0, seconds = 0, rmse = 0, denoised_seconds = 0, denoised_rmse = 0;
  while (std::getline(csv, line)) {
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf,%*f,%*f,%*f,%*f,%lf,%lf", &spp, &seconds, &rmse,
                          &denoised_seconds, &denoised_rmse), 5) << line;
    EXPECT_GT(denoised_seconds, seconds) << line;  // the same samples, then the guides and OIDN
    ++rows;
  }
  EXPECT_EQ(rows, 4);  // 1, 2, 4, 8 spp
  EXPECT_EQ(spp, 8);
  // The images are the table's: the last level's RMSE again from its files. Over the whole
  // image the denoised one is further off (the light's edge blurs: docs/accuracy.md); away from
  // the light it is the closer one.
  const RgbImage ref = read_image(kSource + "/tests/data/reference/cbox/ref_unbounded.exr");
  const RgbImage raw = read_image(dir / "raw-8.exr"), denoised = read_image(dir / "denoised-8.exr");
  EXPECT_NEAR(test::rmse(raw, ref), rmse, 1e-5);
  EXPECT_NEAR(test::rmse(denoised, ref), denoised_rmse, 1e-5);
  EXPECT_LT(masked_rmse(denoised, ref, false), masked_rmse(raw, ref, false) / 2);
  EXPECT_NE(file_bytes(dir / "c.md").find("raw RMSE at this time"), std::string::npos);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace tessera
