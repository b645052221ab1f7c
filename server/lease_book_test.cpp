// Leases answered from memory (server/lease_book.h, for the lease p99): a LeaseUnit or
// Heartbeat call takes no store lock and runs no statement; the book stays in step with the
// store across a restart, expiry, cancel and delete; a grant the store no longer allows is void.
// Counts (lock acquisitions, statements, units), never times.
#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <map>
#include <set>
#include <thread>

#include "coordinator.h"
#include "fake_clock.h"
#include "farm_error.h"
#include "lease_book.h"
#include "leasing.h"
#include "worker_rates.h"
#include "store_fixture.h"

namespace tessera::server {
namespace {

using testing::tiny_bundle;

/// A 32x32 job in 8x8 tiles (16 tiles) of `spp` batches of 1 spp.
v1::JobRequestOptions options_of(uint32_t spp) {
  v1::JobRequestOptions options;
  options.set_width(32);
  options.set_height(32);
  options.set_tile_size(8);
  options.set_spp(spp);
  options.set_batch_spp(1);
  return options;
}

/// A job of 16 units, one batch of `spp` per tile: 32x32 in 8x8 tiles (unit: 64 x spp samples),
/// or, with `tile` 64, 256x256 in 64x64 tiles (4096 x spp).
v1::JobRequestOptions one_batch_units(uint32_t spp, int tile = 8) {
  v1::JobRequestOptions options;
  options.set_width(4 * tile);
  options.set_height(4 * tile);
  options.set_tile_size(tile);
  options.set_spp(spp);
  options.set_batch_spp(spp);
  return options;
}

class LeaseBookTest : public ::testing::Test {
 protected:
  LeaseBookTest() {
    dir_ = std::filesystem::temp_directory_path() /
           ("tessera-lease-book-test-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    config_.db_path = (dir_ / "farm.db").string();
    config_.output_dir = dir_ / "outputs";
    config_.lease_ms = 30'000;
    farm_.emplace(config_, clock_);
    farm_->resume();
  }
  ~LeaseBookTest() override {
    farm_.reset();
    std::filesystem::remove_all(dir_);
  }

  std::vector<LeasedUnit> look(int64_t worker, uint32_t n) {
    return farm_->lease_units(worker, n, std::chrono::milliseconds(0), [] { return false; });
  }
  UnitResult result(const LeasedUnit& u) {
    return testing::result_for(u.lease, testing::StoreFixture::synthetic(
                                            u.rect, u.lease.batch, u.sample_end - u.sample_begin));
  }
  /// A server crash and start: the coordinator is dropped without its clean shutdown.
  void restart() {
    farm_.reset();
    farm_.emplace(config_, clock_);
    farm_->resume();
  }

  std::filesystem::path dir_;
  testing::FakeClock clock_;
  CoordinatorConfig config_;
  std::optional<Coordinator> farm_;
};

using Unit = std::pair<uint32_t, uint32_t>;  // (tile, batch)

std::set<Unit> units_of(const std::vector<LeasedUnit>& units) {
  std::set<Unit> out;
  for (const LeasedUnit& u : units) out.insert({u.lease.tile, u.lease.batch});
  return out;
}

TEST_F(LeaseBookTest, ALeaseAndAHeartbeatTakeNoStoreLockAndRunNoStatement) {
  farm_->submit(tiny_bundle(), options_of(4), 0, "c");
  const int64_t worker = farm_->register_worker({"w", 4, "avx2", "test"});
  const int64_t idle = farm_->register_worker({"i", 4, "avx2", "test"});
  const uint64_t locks = farm_->store_lock_acquisitions();
  const uint64_t statements = farm_->store_counters().statements;
  // Units without a row, the job's start, the same leases handed again, heartbeats, and an
  // idle worker's empty looks.
  const std::vector<LeasedUnit> first = look(worker, 16);
  ASSERT_EQ(first.size(), 16u);
  ASSERT_EQ(look(worker, 16).size(), 16u);  // the same 16, expiry extended
  ASSERT_EQ(look(worker, 32).size(), 32u);
  for (const LeasedUnit& u : first) {
    EXPECT_TRUE(farm_->heartbeat(worker, u.lease.lease_id).has_value());
  }
  EXPECT_EQ(look(idle, 32).size(), 32u);  // the last 32
  EXPECT_EQ(look(idle, 32).size(), 32u);  // its own, again
  EXPECT_EQ(farm_->store_lock_acquisitions() - locks, 1u)
      << "only the store_counters() read above takes the store's lock";
  EXPECT_EQ(farm_->store_counters().statements - statements, 0u);
  // The leases reach the store with its next operation: every result is accepted.
  std::vector<UnitResult> results;
  for (const LeasedUnit& u : first) results.push_back(result(u));
  for (const AcceptOutcome& o : farm_->upload_all(results)) EXPECT_TRUE(o.accepted) << o.reason;
}

TEST_F(LeaseBookTest, AnUploadTakesTheStoreLockOnlyForItsCommit) {
  // The upload's checks before its decode (the worker known, each result's tile and its size)
  // are answered from memory as a lease's are, once the server has seen the worker and the
  // tiles: a call takes the store's lock once, for the transaction that accepts its results,
  // not once more before it (BENCHMARKS.md, "Lease latency and capacity": under load that
  // second, plain acquisition waited behind every upload group).
  farm_->submit(tiny_bundle(), options_of(4), 0, "c");  // 16 tiles x 4 batches
  const int64_t worker = farm_->register_worker({"w", 4, "avx2", "test"});
  const auto upload = [&](const std::vector<LeasedUnit>& units) {
    std::vector<UnitResult> results;
    for (const LeasedUnit& u : units) results.push_back(result(u));
    for (const AcceptOutcome& o : farm_->upload_all(results)) EXPECT_TRUE(o.accepted) << o.reason;
  };
  upload(look(worker, 16));  // batch 0 of every tile: the tiles are read from the store here
  for (int call = 0; call < 2; ++call) {
    const std::vector<LeasedUnit> units = look(worker, 16);  // batch 1, then 2, of every tile
    ASSERT_EQ(units.size(), 16u);
    const uint64_t locks = farm_->store_lock_acquisitions();
    upload(units);
    EXPECT_EQ(farm_->store_lock_acquisitions() - locks, 1u) << "call " << call;
  }
  // A tile or a worker the server does not know is still refused (from the store).
  const std::vector<LeasedUnit> last = look(worker, 16);
  ASSERT_EQ(last.size(), 16u);
  UnitResult unknown_tile = result(last.front());
  unknown_tile.tile = 99;
  try {
    farm_->upload(unknown_tile);
    ADD_FAILURE() << "an unknown tile was accepted";
  } catch (const FarmError& e) {
    EXPECT_EQ(e.code(), ErrorCode::not_found) << e.what();
  }
  UnitResult unknown_worker = result(last.front());
  unknown_worker.worker_id = 999;
  try {
    farm_->upload(unknown_worker);
    ADD_FAILURE() << "an unknown worker's result was accepted";
  } catch (const FarmError& e) {
    EXPECT_EQ(e.code(), ErrorCode::failed_precondition) << e.what();
  }
  upload(last);
}

TEST_F(LeaseBookTest, UploadCallsWaitingTogetherCommitSixteenAtATime) {
  // 64 workers' calls of 16 results line up behind a commit: they are committed (and answered)
  // in groups of at most 256 results, 16 calls, so at most 16 workers come back at once
  // (ResultIntake::kResultsPerCommit; BENCHMARKS.md, "Lease latency and capacity").
  constexpr int kWorkers = 64;
  std::atomic<bool> held{false};
  config_.before_upload_commit = [&](size_t) {
    if (held.exchange(true)) return;
    // The first call's commit waits until every other call waits behind it.
    while (farm_->upload_calls_waiting() < size_t(kWorkers - 1)) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  };
  restart();
  farm_->submit(tiny_bundle(), options_of(64), 0, "c");  // 16 tiles x 64 batches
  std::vector<std::vector<UnitResult>> calls(kWorkers);
  for (int w = 0; w < kWorkers; ++w) {
    const int64_t worker = farm_->register_worker({"w" + std::to_string(w), 4, "avx2", "test"});
    for (const LeasedUnit& u : look(worker, 16)) calls[size_t(w)].push_back(result(u));
    ASSERT_EQ(calls[size_t(w)].size(), 16u);
  }
  const auto [groups0, calls0] = farm_->upload_groups();
  std::vector<std::thread> threads;
  std::atomic<int> accepted{0};
  for (int w = 0; w < kWorkers; ++w) {
    threads.emplace_back([&, w] {
      for (const AcceptOutcome& o : farm_->upload_all(calls[size_t(w)])) accepted += o.accepted;
    });
  }
  for (std::thread& t : threads) t.join();
  EXPECT_EQ(accepted.load(), kWorkers * 16);
  const auto [groups, committed] = farm_->upload_groups();
  EXPECT_EQ(committed - calls0, uint64_t(kWorkers));
  // The first call alone, then the 63 waiting ones 16 at a time: 16, 16, 16, 15.
  EXPECT_EQ(groups - groups0, 5u);
}

TEST_F(LeaseBookTest, AfterARestartEveryLeaseIsVoidAndItsUnitIsLeasedAgain) {
  const int64_t job = farm_->submit(tiny_bundle(), options_of(2), 0, "c").id;  // 32 units
  const int64_t a = farm_->register_worker({"a", 4, "avx2", "test"});
  const std::vector<LeasedUnit> written = look(a, 8);
  ASSERT_EQ(written.size(), 8u);
  // One result: its call writes the 8 leases to the store first.
  ASSERT_TRUE(farm_->upload(result(written.front())).accepted);
  const std::vector<LeasedUnit> unwritten = look(a, 16);  // 7 held + 9 new, never written
  ASSERT_EQ(unwritten.size(), 16u);
  restart();
  // The 7 written leases were revoked (counted as expired), the 9 others never reached the
  // store: all 31 units not merged are leasable again, each once.
  const int64_t b = farm_->register_worker({"b", 4, "avx2", "test"});
  const std::vector<LeasedUnit> again = look(b, 64);
  EXPECT_EQ(again.size(), 31u);
  EXPECT_EQ(units_of(again).size(), 31u);
  EXPECT_FALSE(units_of(again).contains({written.front().lease.tile, 0}));
  EXPECT_EQ(farm_->job(job).counters.leases_expired, 7u);
  // The old worker's leases are gone: heartbeats not valid, results dropped (not merged twice).
  EXPECT_FALSE(farm_->heartbeat(a, unwritten.back().lease.lease_id).has_value());
  const AcceptOutcome late = farm_->upload(result(unwritten[1]));
  EXPECT_FALSE(late.accepted);
  std::vector<UnitResult> results;
  for (const LeasedUnit& u : again) results.push_back(result(u));
  for (const AcceptOutcome& o : farm_->upload_all(results)) EXPECT_TRUE(o.accepted) << o.reason;
  EXPECT_EQ(farm_->job(job).state, JobState::done);
}

TEST_F(LeaseBookTest, AnExpiredLeaseGoesBackToTheQueueAndAHeartbeatKeepsOneAlive) {
  farm_->submit(tiny_bundle(), options_of(1), 0, "c");  // 16 units
  const int64_t a = farm_->register_worker({"a", 4, "avx2", "test"});
  const int64_t b = farm_->register_worker({"b", 4, "avx2", "test"});
  const std::vector<LeasedUnit> held = look(a, 4);
  ASSERT_EQ(held.size(), 4u);
  ASSERT_EQ(look(b, 12).size(), 12u);
  clock_.advance(config_.lease_ms / 2);
  // A keeps its first lease alive; the three others lapse.
  ASSERT_TRUE(farm_->heartbeat(a, held[0].lease.lease_id).has_value());
  clock_.advance(config_.lease_ms / 2 + 1);
  EXPECT_EQ(farm_->expire_leases(), 12 + 3);  // b's 12 (it never heartbeated) and a's 3
  EXPECT_TRUE(farm_->heartbeat(a, held[0].lease.lease_id).has_value());
  EXPECT_FALSE(farm_->heartbeat(a, held[1].lease.lease_id).has_value());
  const int64_t c = farm_->register_worker({"c", 4, "avx2", "test"});
  const std::vector<LeasedUnit> again = look(c, 64);
  EXPECT_EQ(again.size(), 15u);
  EXPECT_FALSE(units_of(again).contains({held[0].lease.tile, held[0].lease.batch}));
  EXPECT_TRUE(units_of(again).contains({held[1].lease.tile, held[1].lease.batch}));
  EXPECT_FALSE(farm_->upload(result(held[1])).accepted);  // a's expired lease
  EXPECT_TRUE(farm_->upload(result(held[0])).accepted);   // the one it kept alive
}

TEST_F(LeaseBookTest, CancelAndDeleteWhileLeasedEndTheLeases) {
  const int64_t job = farm_->submit(tiny_bundle(), options_of(2), 0, "c").id;
  const int64_t a = farm_->register_worker({"a", 4, "avx2", "test"});
  const std::vector<LeasedUnit> written = look(a, 4);
  ASSERT_TRUE(farm_->upload(result(written[0])).accepted);  // the 4 leases are in the store
  const std::vector<LeasedUnit> held = look(a, 8);           // 3 written, 5 only in the book
  ASSERT_EQ(held.size(), 8u);
  farm_->cancel(job);
  EXPECT_TRUE(look(a, 8).empty());  // nothing held, nothing leasable
  EXPECT_EQ(farm_->leases_held(), 0u);
  for (const LeasedUnit& u : held) {
    EXPECT_FALSE(farm_->heartbeat(a, u.lease.lease_id).has_value());
    const AcceptOutcome o = farm_->upload(result(u));
    EXPECT_FALSE(o.accepted);  // dropped as a cancelled unit's, not an error
  }
  const uint64_t lost = farm_->workers().front().units_lost;
  EXPECT_EQ(lost, 0u);  // a cancelled unit is not the worker's loss
  farm_->remove(job);
  EXPECT_TRUE(look(a, 8).empty());
  // A new job leases from the start.
  farm_->submit(tiny_bundle(), options_of(1), 0, "c");
  EXPECT_EQ(look(a, 64).size(), 16u);
}

TEST_F(LeaseBookTest, PriorityAndAFailureBlockAreFollowed) {
  const int64_t low = farm_->submit(tiny_bundle(), options_of(1), 0, "c").id;
  const int64_t high = farm_->submit(tiny_bundle(), options_of(1), 0, "c").id;
  farm_->set_priority(high, 5);
  const int64_t a = farm_->register_worker({"a", 4, "avx2", "test"});
  const std::vector<LeasedUnit> two = look(a, 2);
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(two[0].lease.job_id, high);
  // Two failures on `high` block `a` from it (WorkerHealthPolicy::failures_to_block).
  for (const LeasedUnit& u : two) {
    ASSERT_TRUE(farm_->release(a, u.lease.lease_id, ReleaseReason::failed, "boom").released);
  }
  const std::vector<LeasedUnit> next = look(a, 1);
  ASSERT_EQ(next.size(), 1u);
  EXPECT_EQ(next[0].lease.job_id, low);
  const int64_t b = farm_->register_worker({"b", 4, "avx2", "test"});
  const std::vector<LeasedUnit> theirs = look(b, 1);
  ASSERT_EQ(theirs.size(), 1u);
  EXPECT_EQ(theirs[0].lease.job_id, high);  // the released units, first in (batch, tile) order
  EXPECT_EQ(theirs[0].lease.tile, two[0].lease.tile);
}

// ---- Leasing by samples (leasing.h, lease_sample_budget) ----------------------------------

TEST(LeaseSampleBudget, OneSecondOfTheMeasuredRateOrASmallShareBeforeAnyResult) {
  WorkerRates::Rate rate;
  rate.threads = 4;
  EXPECT_EQ(lease_sample_budget(rate), 4 * kUnmeasuredSamples);
  rate.threads = 0;  // a worker that did not say: one thread
  EXPECT_EQ(lease_sample_budget(rate), kUnmeasuredSamples);
  rate.threads = 4;
  rate.samples_per_s = 3200.0 * 4;  // 3,200 samples/s per thread, 4 threads
  EXPECT_EQ(lease_sample_budget(rate), 12'800u);
  rate.samples_per_s = 0.0;
  EXPECT_EQ(lease_sample_budget(rate), 0u);  // one unit a call (LeaseBook::lease_up_to)
}

TEST(WorkerRates, SamplesOverRenderTimeRecentResultsWeighingMore) {
  WorkerRates rates;
  EXPECT_FALSE(rates.of(1).samples_per_s.has_value());
  EXPECT_EQ(rates.of(1).threads, 1u);
  rates.set_threads(1, 8);
  rates.record(1, 1000, 10);
  EXPECT_EQ(rates.of(1).threads, 8u);
  EXPECT_DOUBLE_EQ(*rates.of(1).samples_per_s, 100'000.0);
  rates.record(1, 100, 10);  // (1000 x 0.75 + 100) / (10 x 0.75 + 10) per ms
  EXPECT_DOUBLE_EQ(*rates.of(1).samples_per_s, 850.0 / 17.5 * 1000.0);
  rates.record(2, 500, 0);  // under a millisecond counts as one
  EXPECT_DOUBLE_EQ(*rates.of(2).samples_per_s, 500'000.0);
  EXPECT_FALSE(rates.of(3).samples_per_s.has_value());
}

// A worker whose results measure R samples/s per thread on T threads, asking for 16 units of S
// samples, gets max(1, floor(R x T x 1 s / S)) of them; the workers list shows what it holds.
TEST_F(LeaseBookTest, AMeasuredWorkerLeasesAboutOneSecondOfItsRateAndAtLeastOneUnit) {
  const int64_t w = farm_->register_worker({"w", 4, "avx2", "test"});
  farm_->submit(tiny_bundle(), options_of(1), 0, "c");  // 16 units of 64 samples
  const std::vector<LeasedUnit> tiny = look(w, 16);
  ASSERT_EQ(tiny.size(), 16u);  // 1,024 samples, within 4 x 65,536 before any result
  std::vector<UnitResult> results;
  for (const LeasedUnit& u : tiny) {
    results.push_back(result(u));
    results.back().render_ms = 5;  // 64 samples in 5 ms: R x T = 12,800 samples/s
  }
  for (const AcceptOutcome& o : farm_->upload_all(results)) ASSERT_TRUE(o.accepted) << o.reason;
  // S = 64 x 16 = 1,024: floor(12,800 / 1,024) = 12 of the 16 asked.
  farm_->submit(tiny_bundle(), one_batch_units(16), 0, "c");
  const std::vector<LeasedUnit> held = look(w, 16);
  EXPECT_EQ(held.size(), 12u);
  // Asked again (a reply lost): the same 12, and nothing more while they fill the budget.
  EXPECT_EQ(look(w, 16).size(), 12u);
  ASSERT_EQ(farm_->workers().size(), 1u);
  EXPECT_EQ(farm_->workers().front().units_held, 12u);
  // Named as delivering they no longer count: the 4 left fit.
  std::vector<std::string> delivering;
  for (const LeasedUnit& u : held) delivering.push_back(u.lease.lease_id);
  EXPECT_EQ(farm_->lease_units(w, 16, std::chrono::milliseconds(0), nullptr, delivering).size(),
            4u);
  EXPECT_EQ(farm_->workers().front().units_held, 16u);
  std::vector<UnitResult> next;
  for (const LeasedUnit& u : look(w, 16)) next.push_back(result(u));
  for (UnitResult& r : next) r.render_ms = 80;  // 1,024 samples in 80 ms: the same rate
  for (const AcceptOutcome& o : farm_->upload_all(next)) ASSERT_TRUE(o.accepted) << o.reason;
  EXPECT_EQ(farm_->workers().front().units_held, 0u);
  // Units of 4,096 x 1,024 samples (over a second of this worker's work each): one at a time.
  farm_->submit(tiny_bundle(), one_batch_units(1024, 64), 0, "c");
  EXPECT_EQ(look(w, 16).size(), 1u);
  EXPECT_EQ(look(w, 16).size(), 1u);  // the same one
}

// Before any result a worker leases 65,536 samples per render thread: small units travel many
// to a call, large ones one at a time, and two workers asking for a large job's 16 units get
// one each (the farm's finding: one worker held them all while the other idled).
TEST_F(LeaseBookTest, AnUnmeasuredWorkerLeasesASmallShareAndTheOtherWorkerGetsUnitsToo) {
  const int64_t two = farm_->register_worker({"two", 2, "avx2", "test"});
  const int64_t one = farm_->register_worker({"one", 1, "avx2", "test"});
  farm_->submit(tiny_bundle(), one_batch_units(1024), 0, "c");  // 16 units of 65,536 samples
  EXPECT_EQ(look(two, 16).size(), 2u);
  EXPECT_EQ(look(one, 16).size(), 1u);
  // 16 units of 4 M samples, first by priority.
  const int64_t large = farm_->submit(tiny_bundle(), one_batch_units(1024, 64), 5, "c").id;
  const int64_t a = farm_->register_worker({"a", 1, "avx2", "test"});
  const int64_t b = farm_->register_worker({"b", 1, "avx2", "test"});
  for (const int64_t w : {a, b}) {
    const std::vector<LeasedUnit> got = look(w, 16);
    ASSERT_EQ(got.size(), 1u);
    EXPECT_EQ(got[0].lease.job_id, large);
  }
  std::map<int64_t, uint32_t> held;
  for (const WorkerRecord& w : farm_->workers()) held[w.id] = w.units_held;
  EXPECT_EQ(held, (std::map<int64_t, uint32_t>{{two, 2}, {one, 1}, {a, 1}, {b, 1}}));
}

/// Job 7, running: two 8x8 tiles of 4 batches of 1 spp, every unit queued.
LeaseBookJob two_tile_job() {
  LeaseBookJob job;
  job.job_id = 7;
  job.state = JobState::running;
  job.spec.options.width = 16;
  job.spec.options.height = 8;
  job.spec.options.tile_size = 8;
  job.spec.options.spp = 4;
  job.spec.options.batch_spp = 1;
  job.tiles = {{{0, 0, 8, 8}, 0}, {{8, 0, 16, 8}, 0}};
  job.queue = {{0, 0, 4}, {1, 0, 4}};
  return job;
}

// The book on its own: a grant made after the store's state was read is applied again when the
// job is put again, or void when the store's new state no longer has its unit leasable.
TEST(LeaseBook, AGrantTheStoreNoLongerAllowsIsVoidWhenTheJobIsPutAgain) {
  testing::FakeClock clock;
  LeaseBook book(clock, 1000);
  book.add_worker(1, "");
  LeaseBookJob job = two_tile_job();
  book.put_job(job);
  const std::vector<LeasedUnit> got = book.lease_up_to(1, 2);
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got[0].lease.tile, 0u);
  EXPECT_EQ(got[1].lease.tile, 1u);
  // The store, read before either grant was written: tile 0 still open, tile 1 closed.
  job.queue = {{0, 0, 4}, {1, 0, 0}};
  book.put_job(job);
  EXPECT_EQ(book.voided(), 1u);
  EXPECT_TRUE(book.extend(1, got[0].lease.lease_id).has_value());
  EXPECT_FALSE(book.extend(1, got[1].lease.lease_id).has_value());
  const std::vector<LeaseBook::Grant> journal = book.take_journal();
  ASSERT_EQ(journal.size(), 1u);
  EXPECT_EQ(journal[0].lease.lease_id, got[0].lease.lease_id);
  // Tile 0's next unit is batch 1 (the kept grant took batch 0).
  const std::vector<LeasedUnit> next = book.lease_up_to(1, 2);
  ASSERT_EQ(next.size(), 2u);
  EXPECT_EQ(next[1].lease.tile, 0u);
  EXPECT_EQ(next[1].lease.batch, 1u);
}

// A worker leasing while its last call's results are on their way names those leases as
// delivering: they are neither returned nor counted in max_units, so it gets new units, and
// their expiry is still extended; a lease retried without them returns every lease held.
TEST(LeaseBook, LeasesBeingDeliveredAreExtendedButNotReturnedOrCounted) {
  testing::FakeClock clock;
  LeaseBook book(clock, 1000);
  book.add_worker(1, "");
  book.put_job(two_tile_job());
  const std::vector<LeasedUnit> first = book.lease_up_to(1, 2);
  ASSERT_EQ(first.size(), 2u);
  const std::vector<std::string> delivering = {first[0].lease.lease_id, first[1].lease.lease_id};
  clock.advance(600);
  const std::vector<LeasedUnit> next = book.lease_up_to(1, 2, delivering);
  ASSERT_EQ(next.size(), 2u);  // without the names: the two held leases, nothing new
  for (const LeasedUnit& u : next) {
    EXPECT_NE(u.lease.lease_id, delivering[0]);
    EXPECT_NE(u.lease.lease_id, delivering[1]);
    EXPECT_EQ(u.lease.batch, 1u);
  }
  // Extended by the call: not due 1200 ms after their grant (lease 1000 ms).
  clock.advance(600);
  book.take_journal();  // written to the store
  EXPECT_TRUE(book.due(clock.now_unix_ms()).empty());
  // Without the names (a retry after a lost reply), every lease held comes back.
  EXPECT_EQ(book.lease_up_to(1, 2).size(), 4u);
}

// The book's sample bound: the held leases count first; at least one unit when none is held.
TEST(LeaseBook, HeldLeasesCountAgainstTheSampleBound) {
  testing::FakeClock clock;
  LeaseBook book(clock, 1000);
  book.add_worker(1, "");
  book.put_job(two_tile_job());  // units of 64 samples
  EXPECT_EQ(book.lease_up_to(1, 8, {}, 0).size(), 1u);
  EXPECT_EQ(book.lease_up_to(1, 8, {}, 0).size(), 1u);    // the same one, nothing new
  EXPECT_EQ(book.lease_up_to(1, 8, {}, 191).size(), 2u);  // 64 held + 64 (a third: 192)
  EXPECT_EQ(book.lease_up_to(1, 8, {}, 64 * 5).size(), 5u);
  EXPECT_EQ(book.held_by_worker(), (std::map<int64_t, size_t>{{1, 5}}));
  EXPECT_EQ(book.lease_up_to(1, 8).size(), 8u);  // no bound: the count alone
}

}  // namespace
}  // namespace tessera::server
