// Batched calls: LeaseUnit with max_units leases several units in one call and
// UploadResults delivers several results in one transaction. Workers from before (no
// max_units, UploadResult) keep working; a worker that dies holding K leases loses nothing
// (every lease expires and is leased again; its late results are dropped, none merged twice).
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "accum/accumulation_codec.h"
#include "coordinator.h"
#include "fake_clock.h"
#include "loopback_server.h"
#include "store_fixture.h"
#include "wire/rpc_channel.h"
#include "worker_service.h"

namespace tessera::server {
namespace {

using testing::small_units;
using testing::tiny_bundle;

CoordinatorConfig memory_config() {
  CoordinatorConfig c;
  c.db_path = ":memory:";
  c.output_dir = std::filesystem::temp_directory_path() / "tessera-batched-calls-test";
  return c;
}

/// The encoded result a worker would upload for `unit`.
std::string result_bytes(const v1::WorkUnit& unit) {
  const TileRect rect{unit.x0(), unit.y0(), unit.x1(), unit.y1()};
  return encode_accumulation(testing::StoreFixture::synthetic(
      rect, unit.batch(), unit.sample_end() - unit.sample_begin()));
}

v1::UploadResultRequest upload_of(uint64_t worker, const std::string& lease_id,
                                  const v1::WorkUnit& unit) {
  v1::UploadResultRequest r;
  r.set_worker_id(worker);
  r.set_lease_id(lease_id);
  r.set_job_id(unit.job_id());
  r.set_tile(unit.tile());
  r.set_batch(unit.batch());
  r.set_accumulation(result_bytes(unit));
  r.set_isa("avx2");
  return r;
}

/// WorkerService on 127.0.0.1 over a :memory: store, and a stub speaking to it.
class BatchedCalls : public ::testing::Test {
 protected:
  BatchedCalls() : coordinator_(memory_config(), clock_) {
    server_ = testing::serve_on_loopback({&workers_}, &port_);
    stub_ = v1::WorkerService::NewStub(wire::make_channel("127.0.0.1:" + std::to_string(port_)));
    job_ = coordinator_.submit(tiny_bundle(), small_units(), 0, "c").id;
  }
  ~BatchedCalls() override {
    coordinator_.stop_leasing();
    server_->Shutdown(std::chrono::system_clock::now());
  }

  uint64_t register_worker() {
    return uint64_t(coordinator_.register_worker({"w", 1, "avx2", "test"}));
  }

  v1::LeaseUnitResponse lease(uint64_t worker, uint32_t max_units) {
    v1::LeaseUnitRequest request;
    request.set_worker_id(worker);
    request.set_max_units(max_units);
    v1::LeaseUnitResponse response;
    EXPECT_TRUE(lease_call(request, &response).ok());
    return response;
  }

  grpc::Status lease_call(const v1::LeaseUnitRequest& request, v1::LeaseUnitResponse* response) {
    grpc::ClientContext context;
    wire::prepare_context(context, "", std::chrono::seconds(30));
    return stub_->LeaseUnit(&context, request, response);
  }

  grpc::Status upload_all(const v1::UploadResultsRequest& request,
                          v1::UploadResultsResponse* response) {
    grpc::ClientContext context;
    wire::prepare_context(context, "", std::chrono::seconds(30));
    return stub_->UploadResults(&context, request, response);
  }

  JobCounters counters() { return coordinator_.job(job_).counters; }

  testing::FakeClock clock_;
  Coordinator coordinator_;
  wire::BearerTokenCheck auth_{""};
  WorkerServiceImpl workers_{coordinator_, auth_};
  int port_ = 0;
  std::unique_ptr<grpc::Server> server_;
  std::unique_ptr<v1::WorkerService::Stub> stub_;
  int64_t job_ = 0;
};

TEST_F(BatchedCalls, AWorkerWithoutMaxUnitsGetsOneUnitInTheSingleFields) {
  const uint64_t w = register_worker();
  const v1::LeaseUnitResponse lease = this->lease(w, 0);
  ASSERT_TRUE(lease.leased());
  EXPECT_EQ(lease.leases_size(), 0);
  EXPECT_EQ(lease.lease_id().size(), 32u);
  v1::UploadResultResponse accepted;
  grpc::ClientContext context;
  wire::prepare_context(context, "", std::chrono::seconds(30));
  ASSERT_TRUE(stub_->UploadResult(&context, upload_of(w, lease.lease_id(), lease.unit()), &accepted)
                  .ok());
  EXPECT_TRUE(accepted.accepted());
  EXPECT_EQ(counters().units_done, 1u);
}

// Over the wire: a lease naming its in-flight leases as delivering gets new units; one naming
// more than 64 is refused with INVALID_ARGUMENT saying how many, and leases nothing.
TEST_F(BatchedCalls, DeliveringLeasesAreLeftOutAndMoreThan64AreRefused) {
  const uint64_t w = register_worker();
  const v1::LeaseUnitResponse first = this->lease(w, 4);
  ASSERT_EQ(first.leases_size(), 4);
  v1::LeaseUnitRequest request;
  request.set_worker_id(w);
  request.set_max_units(4);
  for (const v1::UnitLease& l : first.leases()) request.add_delivering(l.lease_id());
  v1::LeaseUnitResponse next;
  ASSERT_TRUE(lease_call(request, &next).ok());
  ASSERT_EQ(next.leases_size(), 4);
  std::set<std::string> ids;
  for (const v1::UnitLease& l : first.leases()) ids.insert(l.lease_id());
  for (const v1::UnitLease& l : next.leases()) EXPECT_TRUE(ids.insert(l.lease_id()).second);
  request.clear_delivering();
  for (int i = 0; i < 65; ++i) request.add_delivering("lease" + std::to_string(i));
  v1::LeaseUnitResponse refused;
  const grpc::Status status = lease_call(request, &refused);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(status.error_message().find("65"), std::string::npos) << status.error_message();
  EXPECT_EQ(refused.leases_size(), 0);
  EXPECT_EQ(counters().units_leased, 8u);
}

TEST_F(BatchedCalls, SeveralUnitsLeasedAndUploadedInOneCallEach) {
  const uint64_t w = register_worker();
  const v1::LeaseUnitResponse lease = this->lease(w, 8);
  ASSERT_EQ(lease.leases_size(), 8);
  EXPECT_TRUE(lease.leased());
  EXPECT_TRUE(lease.lease_id().empty());  // the single fields stay empty
  // In scheduling order: batch 0 of tiles 0..7.
  for (int i = 0; i < 8; ++i) {
    EXPECT_EQ(lease.leases(i).unit().batch(), 0u);
    EXPECT_EQ(lease.leases(i).unit().tile(), uint32_t(i));
  }
  // Asking again without uploading (a lost reply) leases nothing new: the same 8 come back.
  const v1::LeaseUnitResponse again = this->lease(w, 8);
  ASSERT_EQ(again.leases_size(), 8);
  for (int i = 0; i < 8; ++i) EXPECT_EQ(again.leases(i).lease_id(), lease.leases(i).lease_id());

  v1::UploadResultsRequest request;
  request.set_worker_id(w);
  for (const v1::UnitLease& l : lease.leases()) {
    *request.add_results() = upload_of(0, l.lease_id(), l.unit());
  }
  v1::UploadResultsResponse response;
  ASSERT_TRUE(upload_all(request, &response).ok());
  ASSERT_EQ(response.results_size(), 8);
  for (const v1::UploadResultResponse& r : response.results()) EXPECT_TRUE(r.accepted());
  EXPECT_EQ(counters().units_done, 8u);
  EXPECT_EQ(counters().results_merged, 8u);
  // Uploaded again: every one dropped as stale, nothing merged twice.
  ASSERT_TRUE(upload_all(request, &response).ok());
  for (const v1::UploadResultResponse& r : response.results()) EXPECT_FALSE(r.accepted());
  EXPECT_EQ(counters().results_merged, 8u);
  EXPECT_EQ(counters().results_dropped, 8u);
}

TEST_F(BatchedCalls, OneBadResultRefusesTheWholeCallNamingItAndStoresNothing) {
  const uint64_t w = register_worker();
  const v1::LeaseUnitResponse lease = this->lease(w, 3);
  ASSERT_EQ(lease.leases_size(), 3);
  v1::UploadResultsRequest request;
  request.set_worker_id(w);
  for (const v1::UnitLease& l : lease.leases()) {
    *request.add_results() = upload_of(w, l.lease_id(), l.unit());
  }
  // Result 2 carries tile 0's bytes: they do not cover its tile.
  request.mutable_results(2)->set_accumulation(request.results(0).accumulation());
  v1::UploadResultsResponse response;
  const grpc::Status refused = upload_all(request, &response);
  EXPECT_EQ(refused.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(refused.error_message().find("tile 2"), std::string::npos) << refused.error_message();
  EXPECT_NE(refused.error_message().find("none stored"), std::string::npos)
      << refused.error_message();
  EXPECT_EQ(counters().units_done, 0u);
  EXPECT_EQ(counters().results_merged, 0u);
  // The leases are still current: the good results go through.
  request.mutable_results()->RemoveLast();
  ASSERT_TRUE(upload_all(request, &response).ok());
  EXPECT_EQ(counters().units_done, 2u);

  // Another worker's results, and more than the call allows, are refused with a reason.
  request.mutable_results(0)->set_worker_id(w + 1);
  EXPECT_EQ(upload_all(request, &response).error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  v1::UploadResultsRequest many;
  many.set_worker_id(w);
  for (uint32_t i = 0; i <= WorkerServiceImpl::kMaxUnitsPerCall; ++i) {
    *many.add_results() = request.results(1);
  }
  const grpc::Status too_many = upload_all(many, &response);
  EXPECT_EQ(too_many.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(too_many.error_message().find("at most"), std::string::npos);
}

// One Heartbeat with lease_ids renews every lease named, in one call, answering each in order;
// a lease that is gone (here: another worker's, and one handed back) is answered invalid
// without failing the others. Without lease_ids the single-lease answer is as before.
TEST_F(BatchedCalls, OneHeartbeatRenewsEveryLeaseNamedAndAnswersEachInOrder) {
  const uint64_t w = register_worker();
  const uint64_t other = register_worker();
  const v1::LeaseUnitResponse mine = this->lease(w, 3);
  const v1::LeaseUnitResponse theirs = this->lease(other, 1);
  ASSERT_EQ(mine.leases_size(), 3);
  ASSERT_EQ(theirs.leases_size(), 1);
  {
    v1::ReleaseUnitRequest release;
    release.set_worker_id(w);
    release.set_lease_id(mine.leases(1).lease_id());
    v1::ReleaseUnitResponse released;
    grpc::ClientContext context;
    wire::prepare_context(context, "", std::chrono::seconds(30));
    ASSERT_TRUE(stub_->ReleaseUnit(&context, release, &released).ok());
  }
  clock_.advance(1000);
  v1::HeartbeatRequest request;
  request.set_worker_id(w);
  request.set_lease_id(mine.leases(0).lease_id());
  for (int i = 0; i < 3; ++i) request.add_lease_ids(mine.leases(i).lease_id());
  request.add_lease_ids(theirs.leases(0).lease_id());
  v1::HeartbeatResponse response;
  {
    grpc::ClientContext context;
    wire::prepare_context(context, "", std::chrono::seconds(30));
    ASSERT_TRUE(stub_->Heartbeat(&context, request, &response).ok());
  }
  ASSERT_EQ(response.leases_size(), 4);
  EXPECT_TRUE(response.leases(0).valid());
  EXPECT_FALSE(response.leases(1).valid());  // handed back
  EXPECT_TRUE(response.leases(2).valid());
  EXPECT_FALSE(response.leases(3).valid());  // not this worker's
  EXPECT_EQ(response.leases(0).expires_unix_ms(),
            mine.leases(0).expires_unix_ms() + 1000);  // renewed from now
  EXPECT_EQ(response.leases(2).expires_unix_ms(), response.leases(0).expires_unix_ms());
  EXPECT_TRUE(response.valid());  // the first's answer in the single fields too
  EXPECT_EQ(response.expires_unix_ms(), response.leases(0).expires_unix_ms());

  // More leases than a call allows is refused with the limit.
  v1::HeartbeatRequest many;
  many.set_worker_id(w);
  for (size_t i = 0; i <= Coordinator::kMaxLeasesPerHeartbeat; ++i) {
    many.add_lease_ids(mine.leases(0).lease_id());
  }
  grpc::ClientContext context;
  wire::prepare_context(context, "", std::chrono::seconds(30));
  const grpc::Status refused = stub_->Heartbeat(&context, many, &response);
  EXPECT_EQ(refused.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(refused.error_message().find("at most 64"), std::string::npos)
      << refused.error_message();
}

// A worker killed holding K leases: every lease expires and goes to the next worker; the dead
// worker's results, should they still arrive, are dropped; every unit is merged once.
TEST(BatchedLeases, AWorkerLostWithKLeasesLosesNothingAndNothingMergesTwice) {
  testing::FakeClock clock;
  Coordinator farm(memory_config(), clock);
  const int64_t job = farm.submit(tiny_bundle(), small_units(), 0, "c").id;
  const int64_t dead = farm.register_worker({"dead", 1, "avx2", "test"});
  const int64_t alive = farm.register_worker({"alive", 1, "avx2", "test"});
  const auto no_wait = std::chrono::milliseconds(0);
  const auto never = [] { return false; };
  const std::vector<LeasedUnit> lost = farm.lease_units(dead, 8, no_wait, never);
  ASSERT_EQ(lost.size(), 8u);
  clock.advance(farm.lease_ms() + 1);
  EXPECT_EQ(farm.expire_leases(), 8);
  std::set<std::pair<uint32_t, uint32_t>> seen;
  uint32_t merged = 0;
  for (;;) {
    const std::vector<LeasedUnit> units = farm.lease_units(alive, 8, no_wait, never);
    if (units.empty()) break;
    std::vector<UnitResult> results;
    for (const LeasedUnit& u : units) {
      EXPECT_TRUE(seen.insert({u.lease.tile, u.lease.batch}).second) << "leased twice";
      UnitResult r = testing::result_for(
          u.lease, testing::StoreFixture::synthetic(u.rect, u.lease.batch,
                                                    u.sample_end - u.sample_begin));
      results.push_back(std::move(r));
    }
    for (const AcceptOutcome& o : farm.upload_all(results)) {
      EXPECT_TRUE(o.accepted);
      merged += o.accepted;
    }
    clock.advance(1);
  }
  EXPECT_EQ(seen.size(), 64u);  // the 8 lost units were leased again
  EXPECT_EQ(merged, 64u);
  // The dead worker's results arrive late: all dropped.
  std::vector<UnitResult> late;
  for (const LeasedUnit& u : lost) {
    late.push_back(testing::result_for(
        u.lease, testing::StoreFixture::synthetic(u.rect, u.lease.batch,
                                                  u.sample_end - u.sample_begin)));
  }
  for (const AcceptOutcome& o : farm.upload_all(late)) EXPECT_FALSE(o.accepted);
  const JobRecord record = farm.job(job);
  EXPECT_EQ(record.state, JobState::done);
  EXPECT_EQ(record.counters.units_done, 64u);
  EXPECT_EQ(record.counters.results_merged, 64u);
  EXPECT_EQ(record.counters.leases_expired, 8u);
  EXPECT_EQ(record.counters.results_dropped, 8u);
}

}  // namespace
}  // namespace tessera::server
