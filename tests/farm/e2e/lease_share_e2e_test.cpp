// Leasing by samples end to end (docs/farm.md, "Leasing by samples"): after tiny jobs a worker
// asks for 16 units of the last size it saw; the server grants about a second of the worker's
// measured work, so a large job that follows is shared by every idle worker rather than held by
// the first to ask. Asserts on the units each worker delivered, never on times.
#include <gtest/gtest.h>

#include <chrono>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <thread>

#include "farm_cluster.h"

namespace tessera::e2e {
namespace {

const std::string kLeaseShareScene =
    (source_dir() / "tests" / "farm" / "data" / "tiny.json").string();

/// `tessera workers --json`: worker id -> its object.
std::map<uint64_t, nlohmann::json> lease_share_workers(FarmCluster& farm) {
  const CommandResult r = farm.cli({"workers", "--json"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::map<uint64_t, nlohmann::json> out;
  if (r.exit_code != 0) return out;
  for (const nlohmann::json& w : nlohmann::json::parse(r.out)) {
    out[w.at("id").get<uint64_t>()] = w;
  }
  return out;
}

TEST(LeaseShare, AfterTinyJobsALargeJobsUnitsGoToBothWorkers) {
  FarmCluster farm("lease-share");
  farm.start_server();
  farm.start_worker({"--threads", "1"});
  farm.start_worker({"--threads", "1"});
  const auto deadline = std::chrono::steady_clock::now() + kPatience;
  std::map<uint64_t, nlohmann::json> workers;
  while (workers.size() < 2 && std::chrono::steady_clock::now() < deadline) {
    workers = lease_share_workers(farm);
    if (workers.size() < 2) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_EQ(workers.size(), 2u) << "both workers registered";

  // Tiny jobs (one 8x8 unit of 64 samples each) until both workers delivered some: each then
  // asks for 16 units of that size at its next call.
  const auto units_done = [&](const std::map<uint64_t, nlohmann::json>& list) {
    std::map<uint64_t, uint64_t> done;
    for (const auto& [id, w] : list) done[id] = w.at("units_done").get<uint64_t>();
    return done;
  };
  std::map<uint64_t, uint64_t> before;
  int tiny_jobs = 0;
  for (int job = 0; job < 60; ++job) {
    ++tiny_jobs;
    const uint64_t id =
        farm.submit({kLeaseShareScene, "--width", "8", "--height", "8", "--spp", "1"});
    ASSERT_EQ(farm.wait_final(id).state(), v1::JOB_STATE_DONE);
    before = units_done(lease_share_workers(farm));
    if (before.size() == 2 && before.begin()->second > 0 &&
        before.rbegin()->second > 0) {
      break;
    }
  }
  ASSERT_EQ(before.size(), 2u);
  for (const auto& [id, done] : before) ASSERT_GT(done, 0u) << "worker " << id << " rendered none";

  // 16 units of 32x32 pixels x 64 spp = 65,536 samples: more than a second of what a worker's
  // tiny units measured (at most 64 samples a millisecond), so each call is granted one unit
  // until the worker's rate is measured on this job. Without the bound the first worker to ask
  // is granted all 16.
  const uint64_t large =
      farm.submit({kLeaseShareScene, "--width", "128", "--height", "128", "--tile", "32", "--spp",
                   "64", "--batch", "64"});
  const v1::JobInfo done = farm.wait_final(large);
  ASSERT_EQ(done.state(), v1::JOB_STATE_DONE) << done.error();
  ASSERT_EQ(done.counters().units_total(), 16u);

  const std::map<uint64_t, nlohmann::json> after = lease_share_workers(farm);
  ASSERT_EQ(after.size(), 2u);
  std::map<uint64_t, uint64_t> contributed;
  std::cout << "[lease-share] " << tiny_jobs << " tiny jobs; the large job's units by worker:";
  for (const auto& [id, w] : after) {
    contributed[id] = w.at("units_done").get<uint64_t>() - before.at(id);
    std::cout << " " << contributed[id];
  }
  std::cout << " (its wall time " << done.wall_time_s() << " s)" << std::endl;
  uint64_t delivered = 0;
  for (const auto& [id, units] : contributed) {
    EXPECT_GT(units, 0u) << "worker " << id << " contributed nothing to the large job";
    delivered += units;
  }
  EXPECT_EQ(delivered, 16u);
  // The units each worker holds are listed (none once every result is in).
  for (const auto& [id, w] : after) {
    ASSERT_TRUE(w.contains("units_held")) << w.dump();
    EXPECT_EQ(w.at("units_held").get<uint64_t>(), 0u) << "worker " << id;
  }
}

}  // namespace
}  // namespace tessera::e2e
