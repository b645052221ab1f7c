// Spot checks (server/spot_checks.h): the sampling function, the exact comparison, a held result
// merged once another worker agrees, a mismatch decided by a third worker and its worker
// quarantined (through a restart, until released), the bounded wait, and no routing at all for a
// job without checks. Driven through the Coordinator on a fake clock: no sleeps, no processes.
#include <gtest/gtest.h>

#include <bit>
#include <chrono>
#include <cmath>
#include <filesystem>

#include <unistd.h>

#include "accum/accumulation_codec.h"
#include "coordinator.h"
#include "farm_error.h"
#include "fake_clock.h"
#include "store/migrations.h"
#include "store/quarantine_table.h"
#include "store/tiles_table.h"
#include "store_fixture.h"

namespace tessera::server {
namespace {

using testing::FakeClock;

constexpr std::chrono::milliseconds kNoWait{0};

/// One 8x8 tile, 4 batches of 1 spp: 4 units; `rate` checked (1e-9: only the probation checks).
v1::JobRequestOptions spot_check_job(double rate) {
  v1::JobRequestOptions options;
  options.set_width(8);
  options.set_height(8);
  options.set_tile_size(8);
  options.set_spp(4);
  options.set_batch_spp(1);
  options.set_verify_rate(rate);
  return options;
}

/// The unit's result as every correct worker renders it (a function of the unit alone), or with
/// one bit of one sum flipped (a faulty worker).
Accumulation spot_check_sums(const LeasedUnit& unit, bool flipped = false) {
  Accumulation acc(unit.rect);
  for (size_t p = 0; p < acc.pixels(); ++p) {
    acc.count[p] = unit.sample_end - unit.sample_begin;
    acc.rgb[3 * p] = 0.25 * double(p + 1) + unit.lease.batch;
    acc.lum2[p] = 0.5;
  }
  if (flipped) acc.rgb[0] = std::bit_cast<double>(std::bit_cast<uint64_t>(acc.rgb[0]) ^ 1u);
  return acc;
}

struct SpotCheckFarm {
  explicit SpotCheckFarm(const std::string& db = ":memory:", int64_t wait_ms = 60'000) {
    CoordinatorConfig config;
    config.db_path = db;
    config.lease_ms = 10'000;
    config.check_wait_ms = wait_ms;
    config.output_dir = std::filesystem::temp_directory_path() /
                        ("spot_checks_out_" + std::to_string(::getpid()));
    farm = std::make_unique<Coordinator>(config, clock);
  }
  std::vector<LeasedUnit> lease(int64_t worker, uint32_t max_units = 1) {
    return farm->lease_units(worker, max_units, kNoWait, [] { return false; });
  }
  AcceptOutcome deliver(const LeasedUnit& unit, bool flipped = false) {
    return farm->upload(testing::result_for(unit.lease, spot_check_sums(unit, flipped)));
  }
  WorkerRecord worker(int64_t id) {
    for (const WorkerRecord& w : farm->workers()) {
      if (w.id == id) return w;
    }
    return {};
  }
  uint32_t merged(int64_t job) { return farm->job(job).counters.results_merged; }

  FakeClock clock;
  std::unique_ptr<Coordinator> farm;
};

TEST(SpotChecks, SamplingIsAPureFunctionOfTheUnitAtTheRate) {
  for (const double rate : {0.01, 0.05, 0.5}) {
    int sampled = 0;
    const int units = 200'000;
    for (int i = 0; i < units; ++i) {
      const bool s = SpotChecks::sampled(7, uint32_t(i % 500), uint32_t(i / 500), rate);
      EXPECT_EQ(s, SpotChecks::sampled(7, uint32_t(i % 500), uint32_t(i / 500), rate));
      sampled += s;
    }
    EXPECT_NEAR(double(sampled) / units, rate, 0.1 * rate) << rate;
  }
  EXPECT_FALSE(SpotChecks::sampled(1, 0, 0, 0.0));
  EXPECT_TRUE(SpotChecks::sampled(1, 0, 0, 1.0));
  // Another job samples other units.
  int same = 0;
  for (uint32_t b = 0; b < 1000; ++b) {
    same += SpotChecks::sampled(1, 0, b, 0.5) == SpotChecks::sampled(2, 0, b, 0.5);
  }
  EXPECT_LT(same, 600);
}

TEST(SpotChecks, TheComparisonIsBitForBit) {
  LeasedUnit unit;
  unit.rect = TileRect{0, 0, 4, 4};
  unit.sample_end = 2;
  const Accumulation a = spot_check_sums(unit);
  EXPECT_TRUE(SpotChecks::same_bits(a, spot_check_sums(unit)));
  EXPECT_FALSE(SpotChecks::same_bits(a, spot_check_sums(unit, true)));
  Accumulation zero = a, negative_zero = a;
  zero.lum2[3] = 0.0;
  negative_zero.lum2[3] = -0.0;
  EXPECT_FALSE(SpotChecks::same_bits(zero, negative_zero));  // == would call them equal
  Accumulation counted = a;
  ++counted.nan_dropped;
  EXPECT_FALSE(SpotChecks::same_bits(a, counted));
}

TEST(SpotChecks, AHeldResultAndItsWorkersOthersMergeOnceAnotherWorkerAgrees) {
  SpotCheckFarm f;
  const int64_t a = f.farm->register_worker({"a", 1, "avx2", "build"});
  const int64_t b = f.farm->register_worker({"b", 1, "avx2", "build"});
  const int64_t job = f.farm->submit(testing::tiny_bundle(), spot_check_job(1e-9), 0).id;
  const std::vector<LeasedUnit> mine = f.lease(a, 2);
  ASSERT_EQ(mine.size(), 2u);
  // Its first result in the job is held for a check, its second waits on that check.
  EXPECT_TRUE(f.deliver(mine[0]).accepted);
  EXPECT_TRUE(f.deliver(mine[1]).accepted);
  EXPECT_EQ(f.merged(job), 0u);
  // An upload retried after a lost answer is answered the same and still waits.
  EXPECT_TRUE(f.deliver(mine[0]).accepted);
  EXPECT_TRUE(f.deliver(mine[1]).accepted);
  EXPECT_EQ(f.merged(job), 0u);
  // Never its own check.
  for (const LeasedUnit& u : f.lease(a)) EXPECT_NE(u.lease.batch, mine[0].lease.batch);
  // b's next lease starts with the check: the same unit.
  const std::vector<LeasedUnit> theirs = f.lease(b);
  ASSERT_FALSE(theirs.empty());
  EXPECT_EQ(theirs.front().lease.batch, mine[0].lease.batch);
  EXPECT_EQ(theirs.front().lease.tile, mine[0].lease.tile);
  EXPECT_NE(theirs.front().lease.lease_id, mine[0].lease.lease_id);
  ASSERT_TRUE(f.farm->heartbeat(b, theirs.front().lease.lease_id).has_value());
  EXPECT_TRUE(f.deliver(theirs.front()).accepted);
  EXPECT_EQ(f.merged(job), 2u);  // both of a's, in batch order
  const JobRecord record = f.farm->job(job);
  EXPECT_EQ(record.units_checked, 1u);
  EXPECT_EQ(record.units_unverified, 0u);
  EXPECT_EQ(f.worker(a).checks, 1u);
  EXPECT_EQ(f.worker(b).checks, 1u);
  EXPECT_EQ(f.farm->check_totals().mismatches, 0u);
  // a is proven in the job: its next result merges at once.
  std::vector<LeasedUnit> next = f.lease(a);
  ASSERT_FALSE(next.empty());
  EXPECT_TRUE(f.deliver(next.front()).accepted);
  EXPECT_EQ(f.merged(job), 3u);
}

TEST(SpotChecks, AMismatchIsDecidedByAThirdWorkerAndTheOneThatDisagreesIsQuarantined) {
  const std::filesystem::path db = std::filesystem::temp_directory_path() /
                                   ("spot_checks_" + std::to_string(::getpid()) + ".db");
  std::filesystem::remove(db);
  int64_t job = 0;
  {
    SpotCheckFarm f(db.string());
    const int64_t bad = f.farm->register_worker({"bad", 1, "avx2", "build"});
    const int64_t good1 = f.farm->register_worker({"good1", 1, "avx2", "build"});
    const int64_t good2 = f.farm->register_worker({"good2", 1, "avx2", "build"});
    job = f.farm->submit(testing::tiny_bundle(), spot_check_job(1e-9), 0).id;
    const std::vector<LeasedUnit> faulty = f.lease(bad, 2);
    ASSERT_EQ(faulty.size(), 2u);
    EXPECT_TRUE(f.deliver(faulty[0], true).accepted);
    EXPECT_TRUE(f.deliver(faulty[1], true).accepted);  // waits on the first one's check
    const LeasedUnit check1 = f.lease(good1).front();
    ASSERT_EQ(check1.lease.batch, faulty[0].lease.batch);
    EXPECT_TRUE(f.deliver(check1).accepted);
    EXPECT_EQ(f.merged(job), 0u);  // two disagree: a third decides
    const LeasedUnit check2 = f.lease(good2).front();
    ASSERT_EQ(check2.lease.batch, faulty[0].lease.batch);
    EXPECT_TRUE(f.deliver(check2).accepted);
    // The agreed bits merged under the unit's first lease; the waiting result went back.
    EXPECT_EQ(f.merged(job), 1u);
    const WorkerRecord w = f.worker(bad);
    ASSERT_TRUE(w.quarantine.has_value());
    EXPECT_EQ(w.quarantine->job_id, job);
    EXPECT_EQ(w.quarantine->batch, faulty[0].lease.batch);
    EXPECT_NE(w.quarantine->reason.find("differs from 2 other workers'"), std::string::npos)
        << w.quarantine->reason;
    EXPECT_EQ(w.mismatches, 1u);
    EXPECT_FALSE(f.worker(good1).quarantine.has_value());
    EXPECT_EQ(f.farm->quarantined_workers(), 1u);
    EXPECT_TRUE(f.lease(bad).empty());  // no more work
    // The job finishes with the good workers' results only.
    for (int round = 0; round < 8 && f.farm->job(job).state != JobState::done; ++round) {
      for (const int64_t worker : {good1, good2}) {
        for (const LeasedUnit& u : f.lease(worker)) f.deliver(u);
      }
    }
    EXPECT_EQ(f.merged(job), 4u);
  }
  // The quarantine follows the name through a restart and a new registration, until released.
  {
    SpotCheckFarm f(db.string());
    const int64_t again = f.farm->register_worker({"bad", 1, "avx2", "build"});
    ASSERT_TRUE(f.worker(again).quarantine.has_value());
    f.farm->submit(testing::tiny_bundle(), spot_check_job(0), 0);
    EXPECT_TRUE(f.lease(again).empty());
    EXPECT_EQ(f.farm->release_worker(again), "bad");
    EXPECT_FALSE(f.worker(again).quarantine.has_value());
    EXPECT_FALSE(f.lease(again).empty());
    EXPECT_THROW(f.farm->release_worker(again), FarmError);  // not quarantined any more
  }
  std::filesystem::remove(db);
}

// A worker that passed its first check and then went bad: its unchecked result merged; when a
// later check catches it, its tile starts again from zero and the job ends with good bits only.
TEST(SpotChecks, AWorkerCaughtLaterHasTheTilesItTouchedRenderedAgain) {
  const std::filesystem::path db = std::filesystem::temp_directory_path() /
                                   ("spot_checks_redo_" + std::to_string(::getpid()) + ".db");
  std::filesystem::remove(db);
  int64_t job = 0;
  {
    SpotCheckFarm f(db.string());
    const int64_t a = f.farm->register_worker({"turns-bad", 1, "avx2", "build"});
    const int64_t b = f.farm->register_worker({"b", 1, "avx2", "build"});
    const int64_t c = f.farm->register_worker({"c", 1, "avx2", "build"});
    job = f.farm->submit(testing::tiny_bundle(), spot_check_job(1e-9), 0).id;
    // a's first unit (batch 0) is checked by b and agrees: both proven.
    EXPECT_TRUE(f.deliver(f.lease(a).front()).accepted);
    const std::vector<LeasedUnit> bs = f.lease(b);  // the check, then batch 1
    ASSERT_EQ(bs.size(), 2u);
    for (const LeasedUnit& u : bs) EXPECT_TRUE(f.deliver(u).accepted);
    EXPECT_EQ(f.merged(job), 2u);
    // a goes bad: batch 2 merges unchecked.
    const LeasedUnit bad = f.lease(a).front();
    ASSERT_EQ(bad.lease.batch, 2u);
    EXPECT_TRUE(f.deliver(bad, true).accepted);
    EXPECT_EQ(f.merged(job), 3u);
    // c's first unit (batch 3) is checked: a takes the check and disagrees, b decides.
    const LeasedUnit last = f.lease(c).front();
    ASSERT_EQ(last.lease.batch, 3u);
    EXPECT_TRUE(f.deliver(last).accepted);
    const LeasedUnit check_by_a = f.lease(a).front();
    ASSERT_EQ(check_by_a.lease.batch, 3u);
    EXPECT_TRUE(f.deliver(check_by_a, true).accepted);
    const LeasedUnit check_by_b = f.lease(b).front();
    ASSERT_EQ(check_by_b.lease.batch, 3u);
    EXPECT_TRUE(f.deliver(check_by_b).accepted);
    ASSERT_TRUE(f.worker(a).quarantine.has_value());
    // The tile started again: nothing merged, the job still running, its counters consistent.
    JobRecord record = f.farm->job(job);
    EXPECT_EQ(record.state, JobState::running);
    EXPECT_EQ(record.counters.results_merged, 0u);
    EXPECT_EQ(record.counters.units_done, 0u);
    for (int round = 0; round < 12 && f.farm->job(job).state != JobState::done; ++round) {
      for (const int64_t worker : {b, c}) {
        for (const LeasedUnit& u : f.lease(worker)) f.deliver(u);
      }
    }
    record = f.farm->job(job);
    EXPECT_EQ(record.state, JobState::done);
    EXPECT_EQ(record.counters.results_merged, 4u);
    EXPECT_EQ(record.counters.units_done, 4u);
    EXPECT_EQ(record.counters.samples_merged, 4u * 64u);
  }
  // The stored tile is the four good batches, bit for bit.
  Database store(db.string());
  const std::optional<std::string> stored = TilesTable(store).checkpoint(job, 0);
  ASSERT_TRUE(stored.has_value());
  LeasedUnit unit;
  unit.rect = TileRect{0, 0, 8, 8};
  Accumulation expected(unit.rect);
  for (uint32_t b = 0; b < 4; ++b) {
    unit.lease.batch = b;
    unit.sample_begin = b;
    unit.sample_end = b + 1;
    expected.merge(spot_check_sums(unit));
  }
  EXPECT_TRUE(SpotChecks::same_bits(decode_accumulation(*stored), expected));
  std::filesystem::remove(db);
}

TEST(SpotChecks, AHeldResultMergesUnverifiedAfterTheBoundedWait) {
  SpotCheckFarm f(":memory:", 5'000);
  const int64_t a = f.farm->register_worker({"a", 1, "avx2", "build"});
  const int64_t b = f.farm->register_worker({"b", 1, "avx2", "build"});
  const int64_t job = f.farm->submit(testing::tiny_bundle(), spot_check_job(1e-9), 0).id;
  const LeasedUnit unit = f.lease(a).front();
  EXPECT_TRUE(f.deliver(unit).accepted);
  EXPECT_EQ(f.merged(job), 0u);
  // b takes the check but never delivers; b stays online (it calls).
  ASSERT_FALSE(f.lease(b).empty());
  f.clock.advance(4'000);
  f.farm->heartbeat_all(b, {});
  f.farm->expire_leases();
  EXPECT_EQ(f.merged(job), 0u);  // still within the wait
  f.clock.advance(2'000);
  f.farm->heartbeat_all(b, {});
  f.farm->expire_leases();
  EXPECT_EQ(f.merged(job), 1u);
  EXPECT_EQ(f.farm->job(job).units_unverified, 1u);
  EXPECT_EQ(f.farm->check_totals().unverified, 1u);
}

TEST(SpotChecks, WithNoOtherWorkerOfTheBuildAResultMergesAtOnceUnverified) {
  SpotCheckFarm f;
  const int64_t a = f.farm->register_worker({"a", 1, "avx2", "build"});
  f.farm->register_worker({"other build", 1, "avx2", "another build"});
  const int64_t job = f.farm->submit(testing::tiny_bundle(), spot_check_job(1.0), 0).id;
  EXPECT_TRUE(f.deliver(f.lease(a).front()).accepted);
  EXPECT_EQ(f.merged(job), 1u);
  EXPECT_EQ(f.farm->job(job).units_unverified, 1u);
  // A job checking only first units (1e-9) counts the lone worker's first unit once.
  const int64_t second = f.farm->submit(testing::tiny_bundle(), spot_check_job(1e-9), 0).id;
  for (int round = 0; round < 8 && f.merged(second) < 4; ++round) {
    for (const LeasedUnit& u : f.lease(a, 4)) f.deliver(u);
  }
  EXPECT_EQ(f.merged(second), 4u);
  EXPECT_EQ(f.farm->job(second).units_unverified, 1u);
}

TEST(SpotChecks, AQuarantineIsStoredByNameWithTheFinishedJobsItTouched) {
  FakeClock clock;
  Database db(":memory:");
  migrate(db, clock.now_unix_ms());
  QuarantineTable table(db);
  const Quarantine q{3, 1, 2, 1234, "its result of job 3 tile 1 batch 2 differs", {3, 5}};
  table.put("render7", q);
  table.put("render7", Quarantine{9, 0, 0, 99, "later", {}});  // the first reason stands
  ASSERT_EQ(table.all().size(), 1u);
  EXPECT_EQ(table.all().at("render7"), q);
  EXPECT_TRUE(table.finished_jobs_of("render7").empty());  // no units delivered here
  EXPECT_TRUE(table.remove("render7"));
  EXPECT_FALSE(table.remove("render7"));
  EXPECT_TRUE(table.all().empty());
}

TEST(SpotChecks, ARateOutsideZeroToOneIsRefusedNamingIt) {
  SpotCheckFarm f;
  for (const double rate : {-0.1, 1.5, std::nan("")}) {
    try {
      f.farm->submit(testing::tiny_bundle(), spot_check_job(rate), 0);
      ADD_FAILURE() << rate << " was accepted";
    } catch (const FarmError& e) {
      EXPECT_EQ(e.code(), ErrorCode::invalid_argument);
      EXPECT_NE(std::string(e.what()).find("verify rate must be in [0, 1]"), std::string::npos)
          << e.what();
    }
  }
  EXPECT_DOUBLE_EQ(f.farm->submit(testing::tiny_bundle(), spot_check_job(0), 0).verify_rate, 0);
}

TEST(SpotChecks, AJobWithoutChecksIsNotRouted) {
  FakeClock clock;
  SpotChecks checks(clock, 10'000);
  checks.add_worker(1, "a", "build");
  checks.add_worker(2, "b", "build");
  UnitResult r;
  r.worker_id = 1;
  r.lease_id = "lease";
  r.job_id = 3;
  const auto no_checks = [](int64_t) { return 0.0; };
  EXPECT_FALSE(checks.wants({r}, no_checks));
  EXPECT_TRUE(checks.wants({r}, [](int64_t) { return 0.01; }));
  EXPECT_EQ(checks.held(), 0u);
}

}  // namespace
}  // namespace tessera::server
