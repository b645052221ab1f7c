// Progressive jobs end to end: a default job (progressive batches, no --batch) on two workers is
// bit-identical to `tessera-worker render` of the same job, and a time-budget job (`--time 2`,
// 192x192, two workers) ends with every tile above 0 spp and stop reason time_budget. Nothing here
// times the machine: a tile's batch 0 always completes, whatever the speed.
#include <gtest/gtest.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "exr_header.h"
#include "farm_cluster.h"

namespace tessera::e2e {
namespace {

const std::string kCornell = (source_dir() / "scenes" / "cornell.json").string();

std::vector<std::string> concat(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

TEST(ProgressiveE2E, DefaultScheduleBitIdenticalToLocalRender) {
  FarmCluster farm("progressive");
  farm.start_server();
  farm.start_worker();
  farm.start_worker();
  // 4 tiles of 32 px, 64 spp: batches of 1, 1, 2, 4, 8, 16, 32 spp (cap 64), 28 units.
  const std::vector<std::string> options = {"--width", "64", "--height", "64", "--spp", "64",
                                            "--tile", "32"};
  const auto local = farm.dir() / "local.exr";
  const CommandResult r =
      farm.local_render(concat({kCornell, "-q", "-o", local.string()}, options));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const uint64_t id = farm.submit(concat({kCornell}, options));
  ASSERT_NE(id, 0u);
  const v1::JobInfo job = farm.wait_final(id);
  ASSERT_EQ(job.state(), v1::JOB_STATE_DONE) << job.error();
  EXPECT_EQ(job.counters().units_total(), 4u * 7u);
  EXPECT_EQ(job.counters().results_merged(), job.counters().units_total());
  EXPECT_EQ(job.spp_merged(), 64u);
  EXPECT_TRUE(same_pixels(job.output_exr(), local));
  EXPECT_EQ(image_attribute(job.output_exr(), "tessera:batch_schedule"), "progressive");
  EXPECT_EQ(image_attribute(local, "tessera:batch_schedule"), "progressive");
  const CommandResult text = farm.cli({"status", std::to_string(id)});
  EXPECT_NE(text.out.find("every tile has at least 64 of 64 spp"), std::string::npos) << text.out;
  if (HasFailure()) farm.dump_logs();
}

TEST(ProgressiveE2E, TimeJobLeavesNoTileBlack) {
  FarmCluster farm("progressive-time");
  farm.start_server();
  farm.start_worker();
  farm.start_worker();
  const uint64_t id =
      farm.submit({kCornell, "--width", "192", "--height", "192", "--time", "2"});
  ASSERT_NE(id, 0u);
  const v1::JobInfo job = farm.wait_final(id);
  ASSERT_EQ(job.state(), v1::JOB_STATE_DONE) << job.error();
  EXPECT_EQ(job.stop_reason(), v1::STOP_REASON_TIME_BUDGET);
  EXPECT_GT(job.reached().spp_min(), 0u) << "a tile is black";
  const std::vector<float> spp = image_channel(job.output_exr(), "spp");
  ASSERT_EQ(spp.size(), 192u * 192u);
  EXPECT_GT(*std::min_element(spp.begin(), spp.end()), 0.0f);
  if (HasFailure()) farm.dump_logs();
}

TEST(ProgressiveE2E, LocalTimeRenderLeavesNoTileBlack) {
  FarmCluster farm("progressive-time-local");
  const auto out = farm.dir() / "t.exr";
  // A budget shorter than any batch: batch 0 (1 spp) still covers every tile.
  const CommandResult r = farm.local_render({kCornell, "-q", "-o", out.string(), "--width", "64",
                                             "--height", "64", "--time", "0.001"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(image_attribute(out, "tessera:stop_reason"), "time_budget");
  const std::vector<float> spp = image_channel(out, "spp");
  ASSERT_EQ(spp.size(), 64u * 64u);
  EXPECT_GE(*std::min_element(spp.begin(), spp.end()), 1.0f);
}

}  // namespace
}  // namespace tessera::e2e
