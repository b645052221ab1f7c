// The server's gRPC threads are kept between calls (server/app/main.cpp, kMaxPollers): waves of
// concurrent calls are served by the threads the first wave started, not by new ones. Counts
// the threads that served calls in the server's call trace (TESSERA_CALL_TRACE,
// server/call_trace.h); no timing is asserted (calls that happen not to overlap need fewer
// threads, never more).
#include <gtest/gtest.h>

#include <csignal>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>
#include <vector>

#include "farm_cluster.h"

namespace tessera::e2e {
namespace {

// The image module (OpenImageIO's libraries) is loaded before the server listens
// (server/app/main.cpp): while the dynamic loader maps it no thread can start, and gRPC's server
// starts one as a call arrives, so a server that listened first answered nothing meanwhile. The
// port file is the server's last act of starting; by then the log says the module is loaded.
TEST(ServerThreadsE2E, TheImageModuleIsLoadedBeforeTheServerListens) {
  FarmCluster farm("server-module");
  farm.start_server();
  EXPECT_NE(read_text(farm.dir() / "server-0.log").find("tessera-server: image module loaded ("),
            std::string::npos)
      << read_text(farm.dir() / "server-0.log");
}

TEST(ServerThreadsE2E, IdleThreadsServeTheNextCalls) {
  FarmCluster farm("server-threads");
  const std::filesystem::path trace = farm.dir() / "calls.trace";
  farm.set_server_env({"TESSERA_CALL_TRACE=" + trace.string()});
  farm.start_server();
  constexpr int kCalls = 32, kWaves = 6;
  std::vector<uint64_t> workers;
  for (int i = 0; i < kCalls; ++i) {
    v1::RegisterRequest request;
    request.set_name("w" + std::to_string(i));
    v1::RegisterResponse reply;
    ASSERT_TRUE(farm.workers_api().Register(FarmCluster::context().get(), request, &reply).ok());
    workers.push_back(reply.worker_id());
  }
  // Each wave: kCalls long polls at once with nothing to lease (each holds a thread for its
  // wait), then the next wave once all have answered.
  for (int wave = 0; wave < kWaves; ++wave) {
    std::vector<std::thread> threads;
    std::vector<int> ok(kCalls, 0);
    for (int i = 0; i < kCalls; ++i) {
      threads.emplace_back([&, i] {
        v1::LeaseUnitRequest request;
        request.set_worker_id(workers[size_t(i)]);
        request.set_wait_ms(500);
        v1::LeaseUnitResponse reply;
        ok[size_t(i)] =
            farm.workers_api().LeaseUnit(FarmCluster::context().get(), request, &reply).ok() &&
            !reply.leased();
      });
    }
    for (std::thread& t : threads) t.join();
    for (int i = 0; i < kCalls; ++i) EXPECT_TRUE(ok[size_t(i)]) << "wave " << wave << " call " << i;
  }
  ASSERT_EQ(farm.stop_server(SIGTERM), 0);  // the trace is written as the server stops
  std::ifstream in(trace);
  ASSERT_TRUE(in) << "no call trace at " << trace;
  std::set<long> threads;
  int leases = 0;
  for (std::string line; std::getline(in, line);) {
    std::istringstream fields(line);
    std::string kind;
    long tid = 0;
    fields >> kind >> tid;
    if (kind != "lease") continue;
    ++leases;
    threads.insert(tid);
  }
  EXPECT_EQ(leases, kCalls * kWaves);
  // At most kCalls calls were in flight at once: the first wave's threads serve the rest. With
  // gRPC's default of 2 idle threads kept, each wave started about kCalls new ones (about 190
  // in all). The bound leaves a second wave's worth for threads that had not yet gone back to
  // polling when the next wave came (a machine under load), without letting the default pass.
  EXPECT_LE(threads.size(), size_t(2 * kCalls))
      << threads.size() << " threads served " << leases << " long polls in " << kWaves
      << " waves of " << kCalls;
}

}  // namespace
}  // namespace tessera::e2e
