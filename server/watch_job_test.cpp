// WatchJob's rate limit (min_interval_ms) spaces the messages of a running job but never holds
// the final state's: it is sent as soon as the job ends (server/job_service.cpp), so that
// `tessera submit` fetches the image at once instead of up to an interval later.
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <thread>
#include <vector>

#include "coordinator.h"
#include "fake_clock.h"
#include "job_service.h"
#include "loopback_server.h"
#include "store_fixture.h"
#include "wire/rpc_channel.h"

namespace tessera::server {
namespace {

using namespace std::chrono_literals;
using testing::small_units;
using testing::tiny_bundle;

TEST(WatchJob, TheFinalStateIsSentAtOnceWhateverTheInterval) {
  testing::FakeClock clock;
  CoordinatorConfig config;
  config.db_path = ":memory:";
  config.output_dir = std::filesystem::temp_directory_path() / "tessera-watch-job-test";
  Coordinator coordinator(config, clock);
  wire::BearerTokenCheck auth("");
  JobServiceImpl jobs(coordinator, auth);
  int port = 0;
  std::unique_ptr<grpc::Server> server = testing::serve_on_loopback({&jobs}, &port);
  auto stub = v1::JobService::NewStub(wire::make_channel("127.0.0.1:" + std::to_string(port)));
  const int64_t job = coordinator.submit(tiny_bundle(), small_units(), 0, "c").id;

  // A watch asking for at most one message every 3 minutes, with a deadline of 1: the final
  // state can only reach it if it does not wait for the interval. (A server that waits fails
  // this test in a minute and holds its shutdown until the interval ends.)
  grpc::ClientContext context;
  wire::prepare_context(context, "", 60s);
  v1::WatchJobRequest request;
  request.set_job_id(uint64_t(job));
  request.set_min_interval_ms(180'000);
  auto reader = stub->WatchJob(&context, request);
  v1::JobInfo first;
  ASSERT_TRUE(reader->Read(&first));  // the first message comes at once
  EXPECT_NE(first.state(), v1::JOB_STATE_DONE);

  // Every unit leased and its result uploaded: the job ends.
  const int64_t worker = coordinator.register_worker({"w", 1, "avx2", "test"});
  for (;;) {
    const std::vector<LeasedUnit> units = coordinator.lease_units(worker, 16, 0ms, nullptr);
    if (units.empty()) break;
    std::vector<UnitResult> results;
    for (const LeasedUnit& u : units) {
      results.push_back(testing::result_for(
          u.lease, testing::StoreFixture::synthetic(u.rect, u.lease.batch, u.sample_end - u.sample_begin)));
    }
    coordinator.upload_all(results);
  }
  ASSERT_EQ(coordinator.job(job).state, JobState::done);

  v1::JobInfo info, last;
  int messages = 0;
  while (reader->Read(&info)) {
    last = info;
    ++messages;
  }
  const grpc::Status status = reader->Finish();
  EXPECT_TRUE(status.ok()) << wire::status_line(status);  // not DEADLINE_EXCEEDED
  EXPECT_EQ(messages, 1);  // nothing between the first message and the final one
  EXPECT_EQ(last.state(), v1::JOB_STATE_DONE);
  coordinator.stop_leasing();
  server->Shutdown(std::chrono::system_clock::now());
}

}  // namespace
}  // namespace tessera::server
