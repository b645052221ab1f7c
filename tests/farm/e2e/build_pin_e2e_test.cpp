// One renderer build per job end to end (docs/design.md, "The determinism contract"): simulated
// workers register with builds of their own; a job is leased only to the build of the worker its
// first unit went to, through a server restart, unless submitted with --any-build; `tessera
// status --json` and `tessera workers --json` say which build. Asserts on leases and states,
// never on times.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <set>

#include "farm_cluster.h"

namespace tessera::e2e {
namespace {

const std::string kBuildPinScene =
    (source_dir() / "tests" / "farm" / "data" / "tiny.json").string();

uint64_t register_build(FarmCluster& farm, const std::string& name, const std::string& build) {
  v1::RegisterRequest request;
  request.set_name(name);
  request.set_threads(1);
  request.set_version(build);
  v1::RegisterResponse response;
  EXPECT_TRUE(farm.workers_api().Register(FarmCluster::context().get(), request, &response).ok());
  return response.worker_id();
}

v1::LeaseUnitResponse lease_build(FarmCluster& farm, uint64_t worker, uint32_t wait_ms) {
  v1::LeaseUnitRequest request;
  request.set_worker_id(worker);
  request.set_wait_ms(wait_ms);
  v1::LeaseUnitResponse response;
  EXPECT_TRUE(farm.workers_api().LeaseUnit(FarmCluster::context().get(), request, &response).ok());
  return response;
}

nlohmann::json status_json(FarmCluster& farm, uint64_t id) {
  const CommandResult r = farm.cli({"status", std::to_string(id), "--json"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return r.exit_code == 0 ? nlohmann::json::parse(r.out) : nlohmann::json::object();
}

/// 8x8 in one tile, 4 batches of 1 spp: 4 units.
uint64_t submit_four_units(FarmCluster& farm, const std::vector<std::string>& extra = {}) {
  std::vector<std::string> args{kBuildPinScene, "--width", "8", "--height", "8", "--tile", "8",
                                "--spp", "4", "--batch", "1"};
  args.insert(args.end(), extra.begin(), extra.end());
  return farm.submit(args);
}

TEST(BuildPinE2E, AnotherBuildGetsNoUnitOfAPinnedJobThroughARestart) {
  FarmCluster farm("build-pin");
  farm.start_server();
  const uint64_t a = register_build(farm, "sim-a", "build A");
  const uint64_t b = register_build(farm, "sim-b", "build B");
  const uint64_t id = submit_four_units(farm);
  ASSERT_TRUE(lease_build(farm, a, 1000).leased());
  EXPECT_FALSE(lease_build(farm, b, 0).leased()) << "build B leased a unit of a build A job";
  nlohmann::json job = status_json(farm, id);
  EXPECT_EQ(job.value("pinned_build", ""), "build A");
  EXPECT_FALSE(job.value("any_build", true));
  EXPECT_FALSE(job.value("waiting_for_build", true));

  const CommandResult workers = farm.cli({"workers", "--json"});
  ASSERT_EQ(workers.exit_code, 0) << workers.err;
  std::set<std::string> builds;
  for (const nlohmann::json& w : nlohmann::json::parse(workers.out)) {
    builds.insert(w.value("build", ""));
  }
  EXPECT_EQ(builds, (std::set<std::string>{"build A", "build B"}));

  // Build A's only worker stops: the job says what it waits for.
  v1::DeregisterRequest bye;
  bye.set_worker_id(a);
  v1::DeregisterResponse bye_response;
  ASSERT_TRUE(farm.workers_api().Deregister(FarmCluster::context().get(), bye, &bye_response).ok());
  EXPECT_TRUE(status_json(farm, id).value("waiting_for_build", false));
  const CommandResult text = farm.cli({"status", std::to_string(id)});
  EXPECT_NE(text.out.find("no online worker of build build A"), std::string::npos) << text.out;

  farm.kill_server();
  farm.start_server();
  EXPECT_FALSE(lease_build(farm, b, 0).leased()) << "the pin did not survive the restart";
  job = status_json(farm, id);
  EXPECT_EQ(job.value("pinned_build", ""), "build A");
  EXPECT_TRUE(lease_build(farm, a, 1000).leased());
  if (HasFailure()) farm.dump_logs();
}

TEST(BuildPinE2E, AnAnyBuildJobIsLeasedToEveryBuild) {
  FarmCluster farm("any-build");
  farm.start_server();
  const uint64_t a = register_build(farm, "sim-a", "build A");
  const uint64_t b = register_build(farm, "sim-b", "build B");
  const uint64_t id = submit_four_units(farm, {"--any-build"});
  ASSERT_TRUE(lease_build(farm, a, 1000).leased());
  EXPECT_TRUE(lease_build(farm, b, 1000).leased());
  const nlohmann::json job = status_json(farm, id);
  EXPECT_TRUE(job.value("any_build", false));
  EXPECT_TRUE(job.at("pinned_build").is_null());
  if (HasFailure()) farm.dump_logs();
}

}  // namespace
}  // namespace tessera::e2e
