// A tessera-worker process delivers a call's results on a thread of its own while it leases and
// renders its next units (worker/farm/farm_worker.cpp, Deliveries; docs/farm.md, "Batched
// calls"), naming the leases on their way in LeaseUnitRequest.delivering so that the server
// neither answers them again nor counts them. The server here runs in this process, so that
// its upload commit can be held until the worker has leased again: a worker that waits for its
// upload before leasing never does (the hold ends after a minute and the test fails, the job
// still completing).
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>

#include "clock.h"
#include "coordinator.h"
#include "loopback_server.h"
#include "process.h"
#include "store_fixture.h"
#include "wire/bearer_token.h"
#include "worker_service.h"

namespace tessera::server {
namespace {

using namespace std::chrono_literals;
using testing::small_units;
using testing::tiny_bundle;

TEST(WorkerDelivery, AWorkerLeasesAndRendersItsNextUnitsWhileItsResultsAreOnTheirWay) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("tessera-delivery-" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  SystemClock clock;
  CoordinatorConfig config;
  config.db_path = (dir / "farm.db").string();
  config.output_dir = dir / "outputs";
  // The first upload commit waits until the worker holds more leases than the results being
  // committed (whose leases end only with the commit): the next call's, leased while this
  // call's results wait here. A worker that leases only after its upload's answer holds no
  // other lease meanwhile.
  std::atomic<bool> first{true}, leased_meanwhile{false};
  Coordinator* coordinator_ptr = nullptr;
  config.before_upload_commit = [&](size_t results) {
    if (!first.exchange(false)) return;
    const auto until = std::chrono::steady_clock::now() + 60s;
    while (std::chrono::steady_clock::now() < until) {
      if (coordinator_ptr->leases_held() > results) {
        leased_meanwhile = true;
        return;
      }
      std::this_thread::sleep_for(5ms);
    }
  };
  Coordinator coordinator(config, clock);
  coordinator_ptr = &coordinator;
  wire::BearerTokenCheck auth("");
  WorkerServiceImpl workers(coordinator, auth);
  int port = 0;
  std::unique_ptr<grpc::Server> server = testing::serve_on_loopback({&workers}, &port);
  ASSERT_NE(port, 0);

  // 64 units of 64 samples, 16 to a call (the first call: 1).
  const int64_t job = coordinator.submit(tiny_bundle(), small_units(), 0, "test").id;

  {
    e2e::Process worker({TESSERA_WORKER_BIN, "--server", "127.0.0.1:" + std::to_string(port), "--cache",
                    (dir / "cache").string(), "--threads", "1"},
                   dir / "worker.log");
    const auto until = std::chrono::steady_clock::now() + 300s;
    while (coordinator.job(job).state != JobState::done && std::chrono::steady_clock::now() < until) {
      std::this_thread::sleep_for(20ms);
    }
    worker.signal(SIGTERM);
    EXPECT_EQ(worker.wait_for(60s), 0);
  }
  const JobRecord record = coordinator.job(job);
  EXPECT_EQ(record.state, JobState::done);
  std::ifstream log_file(dir / "worker.log");
  const std::string log(std::istreambuf_iterator<char>(log_file), {});
  EXPECT_TRUE(leased_meanwhile) << "the worker waited for its upload before leasing again; its log:\n"
                                << log;
  // Nothing rendered twice, lost or dropped: every unit merged once, from its first lease.
  EXPECT_EQ(record.counters.results_merged, 64u);
  EXPECT_EQ(record.counters.results_dropped, 0u);
  EXPECT_EQ(record.counters.units_released, 0u);
  EXPECT_EQ(record.counters.leases_expired, 0u);
  coordinator.stop_leasing();
  server->Shutdown(std::chrono::system_clock::now());
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace tessera::server
