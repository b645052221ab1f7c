// Denoising on the farm end to end (docs/accuracy.md, "Denoising"): two workers render a
// --denoise --guides job; its raw EXR's R, G, B are the bits of the same job without --denoise,
// its guide channels the bits of `tessera-worker render --guides`, through a server restart
// too; `tessera get --denoised` fetches the denoised file, whose provenance names the
// denoiser. A server that cannot load Open Image Denoise refuses --denoise at submit and
// renders every other job. Needs the library (scripts/install-deps.sh): label "slow", kept out
// of the sanitizer pass like core/denoise's tests.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>

#include "exr_header.h"
#include "farm_cluster.h"

namespace tessera::e2e {
namespace {

const std::string kDenoiseScene = (source_dir() / "scenes" / "cornell.json").string();

/// 48x40 in 16-px tiles, `spp` in batches of 16: batches 0-3 carry guides (the first 64
/// samples), the later ones do not.
std::vector<std::string> denoise_job_args(const std::vector<std::string>& extra = {},
                                          const std::string& spp = "80") {
  std::vector<std::string> args{kDenoiseScene, "--width", "48", "--height", "40", "--tile", "16",
                                "--spp", spp, "--batch", "16"};
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

/// The guide channels of two EXRs equal bit for bit.
::testing::AssertionResult same_guide_channels(const std::filesystem::path& a,
                                               const std::filesystem::path& b) {
  for (const char* name : {"albedo.R", "albedo.G", "albedo.B", "N.X", "N.Y", "N.Z"}) {
    const std::vector<float> x = image_channel(a, name), y = image_channel(b, name);
    if (x.empty() || x.size() != y.size() ||
        std::memcmp(x.data(), y.data(), x.size() * sizeof(float)) != 0) {
      return ::testing::AssertionFailure() << "channel " << name << " of " << a << " (" << x.size()
                                           << " values) differs from " << b << "'s";
    }
  }
  return ::testing::AssertionSuccess();
}

std::filesystem::path local_guides(FarmCluster& farm, const std::string& spp = "80") {
  const auto path = farm.dir() / "local.exr";
  std::vector<std::string> args = denoise_job_args({"--guides", "-q", "-o", path.string()}, spp);
  const CommandResult r = farm.local_render(args);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return path;
}

TEST(DenoiseE2E, FarmGuidesAreTheLocalRendersAndTheRawColourIsUnchanged) {
  FarmCluster farm("denoise");
  farm.start_server();
  farm.start_worker({"--threads", "1"});
  farm.start_worker({"--threads", "1"});
  const uint64_t denoised = farm.submit(denoise_job_args({"--denoise", "--guides"}));
  const uint64_t plain = farm.submit(denoise_job_args());
  const v1::JobInfo d = farm.wait_final(denoised);
  const v1::JobInfo p = farm.wait_final(plain);
  ASSERT_EQ(d.state(), v1::JOB_STATE_DONE) << d.error();
  ASSERT_EQ(p.state(), v1::JOB_STATE_DONE) << p.error();
  EXPECT_TRUE(d.denoise());
  EXPECT_FALSE(p.denoise());
  EXPECT_TRUE(same_pixels(d.output_exr(), p.output_exr()));
  EXPECT_TRUE(image_channel(p.output_exr(), "albedo.R").empty());
  EXPECT_TRUE(same_guide_channels(d.output_exr(), local_guides(farm)));

  EXPECT_EQ(d.denoise_error(), "");
  EXPECT_FALSE(d.output_denoised_exr().empty());
  const auto fetched = farm.dir() / "fetched.denoised.exr";
  const CommandResult get =
      farm.cli({"get", std::to_string(denoised), "--denoised", "-o", fetched.string()});
  ASSERT_EQ(get.exit_code, 0) << get.err;
  EXPECT_NE(image_attribute(fetched, "tessera:denoiser").find("Open Image Denoise"),
            std::string::npos);
  EXPECT_NE(image_attribute(fetched, "tessera:denoiser").find("albedo and normal"),
            std::string::npos);
  EXPECT_FALSE(same_pixels(fetched, p.output_exr()));  // denoised, not the raw image

  // A job without --denoise has no denoised image to get.
  const CommandResult none =
      farm.cli({"get", std::to_string(plain), "--denoised", "-o", (farm.dir() / "x.exr").string()});
  EXPECT_EQ(none.exit_code, 1);
  EXPECT_NE(none.err.find("not submitted with --denoise"), std::string::npos) << none.err;

  // Deleting the job deletes its denoised files with the raw ones.
  EXPECT_EQ(farm.cli({"delete", std::to_string(denoised)}).exit_code, 0);
  EXPECT_FALSE(std::filesystem::exists(d.output_denoised_exr()));
  EXPECT_FALSE(std::filesystem::exists(d.output_denoised_png()));
  if (HasFailure()) farm.dump_logs();
}

TEST(DenoiseE2E, GuidesSurviveAServerRestart) {
  FarmCluster farm("denoise-restart");
  farm.start_server();
  farm.start_worker({"--threads", "1"});
  // 25 batches: the server usually stops while the job runs (any moment gives the same bits).
  const uint64_t id = farm.submit(denoise_job_args({"--denoise", "--guides"}, "400"));
  farm.wait_job(id, [](const v1::JobInfo& j) { return j.counters().results_merged() > 0; },
                "a merged result");
  // The preview (or the final image) of a --guides job holds the guide channels too.
  const auto preview = farm.dir() / "preview.exr";
  ASSERT_EQ(farm.cli({"get", std::to_string(id), "-o", preview.string()}).exit_code, 0);
  EXPECT_EQ(image_channel(preview, "N.Z").size(), size_t(48 * 40));
  farm.kill_server();
  farm.start_server();  // same database, same port: the worker carries on
  const v1::JobInfo done = farm.wait_final(id);
  ASSERT_EQ(done.state(), v1::JOB_STATE_DONE) << done.error();
  EXPECT_TRUE(same_guide_channels(done.output_exr(), local_guides(farm, "400")));
  EXPECT_FALSE(done.output_denoised_exr().empty()) << done.denoise_error();
  if (HasFailure()) farm.dump_logs();
}

TEST(DenoiseE2E, AServerWithoutTheLibraryRefusesDenoiseAndRendersOtherJobs) {
  FarmCluster farm("denoise-missing");
  const auto missing = farm.dir() / "none" / "libOpenImageDenoise.so.2";
  farm.start_server({"--oidn-library", missing.string()});
  farm.start_worker({"--threads", "1"});
  std::vector<std::string> refused{"submit"};
  for (const std::string& a : denoise_job_args({"--denoise"})) refused.push_back(a);
  const CommandResult r = farm.cli(refused);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("cannot denoise"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--oidn-library"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "not one line: " << r.err;
  const v1::JobInfo plain = farm.wait_final(farm.submit(denoise_job_args()));
  EXPECT_EQ(plain.state(), v1::JOB_STATE_DONE) << plain.error();
  if (HasFailure()) farm.dump_logs();
}

}  // namespace
}  // namespace tessera::e2e
