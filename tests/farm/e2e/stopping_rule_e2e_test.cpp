// Stopping rules end to end: a noise job on the Cornell box meets its target tile by tile with
// fewer samples than uniform sampling and the same bits with 1 and 3 workers and locally; a time
// job returns after its budget plus the batches in flight and says what it reached; bad rules are
// refused naming the flag. Nothing here times the machine: the time test bounds only from below by
// the budget (the server's clock) and from above by a generous margin.
#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "accum/accumulation_codec.h"
#include "accum/film.h"
#include "exr_header.h"
#include "farm_cluster.h"
#include "store/sqlite.h"

namespace tessera::e2e {
namespace {

const std::string kCornell = (source_dir() / "scenes" / "cornell.json").string();

std::vector<std::string> concat(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

/// The noise job: target 0.02 on the Cornell box, small enough for CI.
constexpr uint32_t kMaxSpp = 2048;
/// 32x32 pixels in 16 tiles of 8x8: a few million samples per run.
const std::vector<std::string> kNoiseJob = {
    "--width", "32",      "--height", "32",        "--tile",
    "8",       "--noise", "0.02",     "--max-spp", std::to_string(kMaxSpp)};

struct StoredTile {
  uint32_t spp = 0;
  double error = 0;       ///< as stored by the server
  double recomputed = 0;  ///< estimate_relative_error of the stored accumulation
  std::string finished;
};

/// The job's tiles as the server stored them (read-only, beside the running server: WAL).
std::vector<StoredTile> stored_tiles(FarmCluster& farm, uint64_t job_id, uint32_t batch_spp) {
  server::Database db(farm.db_path().string());
  auto q = db.prepare(
      "SELECT t.next_batch, t.error, t.finished, c.accumulation FROM tiles t"
      " LEFT JOIN tile_checkpoints c ON c.job_id = t.job_id AND c.tile = t.tile"
      " WHERE t.job_id = ? ORDER BY t.tile");
  q->bind(1, int64_t(job_id));
  std::vector<StoredTile> out;
  while (q->step()) {
    StoredTile t;
    t.spp = uint32_t(q->int64(0)) * batch_spp;
    t.error = q->real(1);
    t.finished = q->text(2);
    if (!q->is_null(3)) t.recomputed = estimate_relative_error(decode_accumulation(q->blob(3)));
    out.push_back(t);
  }
  return out;
}

TEST(StoppingRuleE2E, NoiseJobMeetsItsTargetSavesSamplesAndIsBitIdentical) {
  FarmCluster farm("noise");
  farm.start_server();
  const auto local = farm.dir() / "local.exr";
  const CommandResult r =
      farm.local_render(concat({kCornell, "-q", "-o", local.string()}, kNoiseJob));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("noise rule"), std::string::npos) << r.err;

  std::vector<std::filesystem::path> outputs;
  for (int workers : {1, 3}) {
    SCOPED_TRACE(std::to_string(workers) + " worker(s)");
    for (int started = workers == 1 ? 0 : 1; started < workers; ++started) farm.start_worker();
    const uint64_t id = farm.submit(concat({kCornell}, kNoiseJob));
    ASSERT_NE(id, 0u);
    const v1::JobInfo job = farm.wait_final(id);
    ASSERT_EQ(job.state(), v1::JOB_STATE_DONE) << job.error();
    EXPECT_TRUE(job.stop_reason() == v1::STOP_REASON_NOISE_TARGET ||
                job.stop_reason() == v1::STOP_REASON_MAX_SPP)
        << job.stop_reason();
    EXPECT_EQ(job.options().batch_spp(), 16u);
    EXPECT_EQ(job.reached().tiles_finished(), 16u);

    // Every tile at or under the target, or at the cap; its stored estimate is the one the
    // shared code computes from its merged samples.
    const std::vector<StoredTile> tiles = stored_tiles(farm, id, 16);
    ASSERT_EQ(tiles.size(), 16u);
    uint64_t samples = 0;
    uint32_t most = 0;
    for (size_t t = 0; t < tiles.size(); ++t) {
      EXPECT_TRUE(tiles[t].error <= 0.02 || tiles[t].spp == kMaxSpp)
          << "tile " << t << ": error " << tiles[t].error << " at " << tiles[t].spp << " spp";
      EXPECT_GE(tiles[t].spp, 16u);
      EXPECT_EQ(tiles[t].error, tiles[t].recomputed) << "tile " << t;
      EXPECT_FALSE(tiles[t].finished.empty());
      samples += uint64_t(8 * 8) * tiles[t].spp;
      most = std::max(most, tiles[t].spp);
    }
    EXPECT_EQ(job.counters().samples_merged(), samples);
    EXPECT_EQ(job.reached().spp_max(), most);
    // Fewer samples than a uniform job at the spp of its most-sampled tile.
    EXPECT_LT(samples, uint64_t(32 * 32) * most);
    EXPECT_LE(job.reached().error_max(), 0.02 + (most == kMaxSpp ? 1.0 : 0.0));

    const auto exr = farm.dir() / ("noise-" + std::to_string(workers) + ".exr");
    const CommandResult got = farm.cli({"get", std::to_string(id), "-o", exr.string()});
    ASSERT_EQ(got.exit_code, 0) << got.err;
    EXPECT_TRUE(same_pixels(exr, local));
    EXPECT_EQ(image_channel(exr, "spp"), image_channel(local, "spp"));
    EXPECT_EQ(image_attribute(exr, "tessera:stop_rule"), "noise");
    outputs.push_back(exr);
  }
  EXPECT_TRUE(same_pixels(outputs[0], outputs[1]));
  if (HasFailure()) farm.dump_logs();
}

TEST(StoppingRuleE2E, TimeJobReturnsAfterItsBudgetAndSaysWhatItReached) {
  FarmCluster farm("time");
  farm.start_server();
  farm.start_worker();
  farm.start_worker();
  // A cap no machine reaches in 10 s (16 tiles x 2^20 spp of 16x16 pixels = 4.4e9 samples),
  // in small units, so the budget, not the cap, ends the job whatever the speed.
  const auto started = std::chrono::steady_clock::now();
  const uint64_t id = farm.submit({kCornell, "--width", "64", "--height", "64", "--tile", "16",
                                   "--batch", "64", "--time", "10", "--max-spp", "1048576"});
  ASSERT_NE(id, 0u);
  const v1::JobInfo job = farm.wait_final(id);
  const double waited_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  ASSERT_EQ(job.state(), v1::JOB_STATE_DONE) << job.error();
  EXPECT_EQ(job.stop_reason(), v1::STOP_REASON_TIME_BUDGET);
  // The server stops leasing at 10 s after the first lease, then awaits what is in flight
  // (units of ~16k samples, bounded by their lease): the margin below is generous on purpose.
  EXPECT_GE(job.wall_time_s(), 10.0);
  EXPECT_LT(job.wall_time_s(), 10.0 + 60.0);
  EXPECT_LT(waited_s, 10.0 + 120.0);
  EXPECT_GT(job.counters().units_skipped(), 0u);
  EXPECT_GT(job.reached().spp_max(), 0u);
  EXPECT_LE(job.reached().spp_min(), job.reached().spp_max());
  EXPECT_EQ(job.counters().units_leased(), 0u);

  // The CLI says what it reached; the EXR carries each pixel's spp.
  const CommandResult status = farm.cli({"status", std::to_string(id), "--json"});
  ASSERT_EQ(status.exit_code, 0) << status.err;
  const nlohmann::json j = nlohmann::json::parse(status.out);
  EXPECT_EQ(j.at("stop_reason"), "time_budget");
  EXPECT_EQ(j.at("stop_rule"), "time");  // the job's one JSON schema (wire/job_json.h)
  EXPECT_EQ(j.at("options").at("time_budget_s"), 10.0);
  EXPECT_EQ(j.at("reached").at("spp_max").get<uint32_t>(), job.reached().spp_max());
  const CommandResult text = farm.cli({"status", std::to_string(id)});
  EXPECT_NE(text.out.find("stopped by time_budget"), std::string::npos) << text.out;
  const std::vector<float> spp = image_channel(job.output_exr(), "spp");
  ASSERT_EQ(spp.size(), 64u * 64u);
  EXPECT_EQ(*std::max_element(spp.begin(), spp.end()), float(job.reached().spp_max()));
  EXPECT_EQ(*std::min_element(spp.begin(), spp.end()), float(job.reached().spp_min()));
  if (HasFailure()) farm.dump_logs();
}

TEST(StoppingRuleE2E, LocalTimeRenderStopsAtItsBudget) {
  FarmCluster farm("time-local");
  const auto out = farm.dir() / "t.exr";
  const CommandResult r =
      farm.local_render({kCornell, "-q", "-o", out.string(), "--width", "32", "--height", "32",
                         "--batch", "16", "--time", "1", "--max-spp", "1048576"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(image_attribute(out, "tessera:stop_reason"), "time_budget");
  EXPECT_GE(std::stod(image_attribute(out, "tessera:wall_time_s")), 1.0);
  EXPECT_FALSE(image_channel(out, "spp").empty());
}

TEST(StoppingRuleE2E, BadRulesAreRefusedNamingTheFlag) {
  FarmCluster farm("bad-rules");
  farm.start_server();
  struct Case {
    std::vector<std::string> args;
    std::string message;
  };
  const std::vector<Case> cases = {
      {{"--noise", "-1"}, "--noise: must be > 0 (got -1)"},
      {{"--time", "0"}, "--time: must be > 0 (got 0)"},
      {{"--spp", "16", "--noise", "0.1"},
       "--spp and --noise are mutually exclusive: give one stopping rule"},
      {{"--spp", "16", "--max-spp", "64"},
       "--max-spp: only with --noise, --time or a noise preset"},
      {{"--preset", "nice"}, "--preset: unknown preset \"nice\""},
  };
  for (const Case& c : cases) {
    // Usage errors (status 2, docs/design.md "Exit statuses"), found before the scene is read.
    const CommandResult r = farm.cli(concat({"submit", kCornell}, c.args));
    EXPECT_EQ(r.exit_code, 2) << c.message;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << r.err;
    const CommandResult local =
        farm.local_render(concat({kCornell, "-q", "-o", (farm.dir() / "x.png").string()}, c.args));
    EXPECT_EQ(local.exit_code, 2) << c.message;
    EXPECT_NE(local.err.find(c.message), std::string::npos) << local.err;
  }
  // A job id that is not a number is a usage error naming the argument; a folder given as the
  // scene is named for what it is (exit 1: the command line parsed, the file is wrong).
  for (const std::string id : {"abc", "-5"}) {
    for (const char* command : {"status", "get", "cancel", "delete", "watch"}) {
      std::vector<std::string> args = {command, id};
      if (std::string(command) == "get") args.insert(args.end(), {"-o", "x.png"});
      const CommandResult r = farm.cli(args);
      EXPECT_EQ(r.exit_code, 2) << command << " " << id;
      EXPECT_NE(r.err.find("job: must be a job id, a whole number (got \"" + id + "\")"),
                std::string::npos)
          << r.err;
    }
  }
  const CommandResult folder = farm.cli({"submit", farm.dir().string()});
  EXPECT_EQ(folder.exit_code, 1);
  EXPECT_NE(folder.err.find(farm.dir().string() + ": is a folder, not a scene file"),
            std::string::npos)
      << folder.err;
  // The server refuses them too (a client that skips local validation).
  v1::SubmitJobRequest request;
  request.mutable_options()->set_noise(0.1);
  request.mutable_options()->set_time_s(3);
  request.mutable_bundle()->set_scene_file("cornell.json");
  auto* file = request.mutable_bundle()->add_files();
  file->set_path("cornell.json");
  std::ifstream in(kCornell);
  file->set_data(std::string(std::istreambuf_iterator<char>(in), {}));
  v1::SubmitJobResponse response;
  const grpc::Status s = farm.jobs().SubmitJob(FarmCluster::context().get(), request, &response);
  EXPECT_EQ(s.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(s.error_message(), "--time and --noise are mutually exclusive: give one stopping rule");
}

}  // namespace
}  // namespace tessera::e2e
