// Spot checks end to end (docs/reliability.md, "Spot checks"): a farm of three workers, one of
// them started with the fault seam TESSERA_FAULT_FLIP_BIT=1 (one bit of every result flipped), a
// job with --verify 0.05. The faulty worker is quarantined at its first unit of the job (its only
// check, which it fails), the job's EXR is bit-identical to `tessera-worker render`, `tessera
// workers --json` shows it quarantined with its reason and the others not, and only the worker
// token releases it. Asserts on states, never on times.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <thread>

#include "farm_cluster.h"

namespace tessera::e2e {
namespace {

const std::string kSpotCheckScene =
    (source_dir() / "tests" / "farm" / "data" / "tiny.json").string();
/// 4 tiles x 8 batches: 32 small units.
const std::vector<std::string> kSpotCheckOptions = {"--width", "32", "--height", "32", "--tile",
                                                    "16",      "--spp", "64", "--batch", "8"};

nlohmann::json workers_json(FarmCluster& farm) {
  const CommandResult r = farm.cli({"workers", "--json"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return r.exit_code == 0 ? nlohmann::json::parse(r.out) : nlohmann::json::array();
}

nlohmann::json worker_named(FarmCluster& farm, const std::string& name) {
  for (const nlohmann::json& w : workers_json(farm)) {
    if (w.value("name", "") == name) return w;
  }
  return nlohmann::json::object();
}

TEST(SpotCheckE2E, AFaultyWorkerIsQuarantinedAtItsFirstUnitAndTheImageIsTheLocalRender) {
  FarmCluster farm("spot-check");
  farm.start_server({"--client-token", "spot-client", "--worker-token", "spot-worker"});
  for (int i = 0; i < 2; ++i) farm.start_worker({"--threads", "1", "--token", "spot-worker"});
  farm.start_worker({"--threads", "1", "--token", "spot-worker"}, {"TESSERA_FAULT_FLIP_BIT=1"});
  // All three registered before the job: a checker is there for every worker's first unit.
  const auto deadline = std::chrono::steady_clock::now() + kPatience;
  while (workers_json(farm).size() < 3 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  std::vector<std::string> submit{kSpotCheckScene};
  submit.insert(submit.end(), kSpotCheckOptions.begin(), kSpotCheckOptions.end());
  submit.insert(submit.end(), {"--verify", "0.05"});
  const uint64_t id = farm.submit(submit);
  const v1::JobInfo job = farm.wait_final(id);
  EXPECT_EQ(job.state(), v1::JOB_STATE_DONE) << job.error();
  EXPECT_EQ(job.counters().results_merged(), job.counters().units_total());
  EXPECT_DOUBLE_EQ(job.verify_rate(), 0.05);

  const auto farm_exr = farm.dir() / "farm.exr";
  const CommandResult got = farm.cli({"get", std::to_string(id), "-o", farm_exr.string()});
  ASSERT_EQ(got.exit_code, 0) << got.err;
  const auto local_exr = farm.dir() / "local.exr";
  std::vector<std::string> local{kSpotCheckScene, "-q", "-o", local_exr.string()};
  local.insert(local.end(), kSpotCheckOptions.begin(), kSpotCheckOptions.end());
  ASSERT_EQ(farm.local_render(local).exit_code, 0);
  EXPECT_TRUE(same_pixels(farm_exr, local_exr));

  const nlohmann::json faulty = worker_named(farm, "e2e-worker-2");
  EXPECT_EQ(faulty.value("state", ""), "quarantined") << faulty.dump();
  ASSERT_TRUE(faulty.contains("quarantine") && faulty["quarantine"].is_object()) << faulty.dump();
  EXPECT_EQ(faulty["quarantine"].value("job", uint64_t(0)), id);
  EXPECT_NE(faulty["quarantine"].value("reason", "").find("differs from"), std::string::npos)
      << faulty.dump();
  // Caught at its first checked unit: one check, failed; nothing of it merged unchecked.
  EXPECT_EQ(faulty.value("checks", 0), 1) << faulty.dump();
  EXPECT_EQ(faulty.value("mismatches", 0), 1) << faulty.dump();
  for (const std::string name : {"e2e-worker-0", "e2e-worker-1"}) {
    const nlohmann::json w = worker_named(farm, name);
    EXPECT_NE(w.value("state", ""), "quarantined") << w.dump();
    EXPECT_TRUE(w["quarantine"].is_null()) << w.dump();
    EXPECT_EQ(w.value("mismatches", -1), 0) << w.dump();
  }

  // The release needs the worker token: the client token is refused.
  const std::string faulty_id = std::to_string(faulty.value("id", 0));
  EXPECT_NE(farm.cli({"workers", "release", faulty_id}).exit_code, 0);
  const CommandResult released =
      farm.cli({"workers", "release", faulty_id}, {"TESSERA_TOKEN=spot-worker"});
  EXPECT_EQ(released.exit_code, 0) << released.err;
  EXPECT_NE(worker_named(farm, "e2e-worker-2").value("state", ""), "quarantined");
  if (HasFailure()) farm.dump_logs();
}

}  // namespace
}  // namespace tessera::e2e
