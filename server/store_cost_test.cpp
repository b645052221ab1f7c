// What the store costs per lease and per accepted result (BENCHMARKS.md, "What a result and a job
// cost the server, counted"): statements executed, statements compiled again, and rows visited
// (SQLite's VM steps), counted by the connection (StoreCounters) through the coordinator's real
// calls. Counts, not times: a bound fails when a change adds statements to the hot paths,
// re-prepares a statement on every call, or makes a lease or an accept visit rows in proportion to
// the units already done.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "accum/accumulation_codec.h"
#include "coordinator.h"
#include "fake_clock.h"
#include "store/integrity.h"
#include "store/results_table.h"
#include "store/tiles_table.h"
#include "store_fixture.h"

namespace tessera::server {
namespace {

using testing::tiny_bundle;

/// Store counters over one lease and one upload, as a worker would do them.
struct CycleCost {
  StoreCounters lease, upload;
};

StoreCounters minus(const StoreCounters& a, const StoreCounters& b) {
  return {a.statements - b.statements, a.reprepares - b.reprepares, a.vm_steps - b.vm_steps,
          a.pages - b.pages};
}

class StoreCost : public ::testing::Test {
 protected:
  StoreCost() {
    config_.db_path = ":memory:";
    config_.output_dir = std::filesystem::temp_directory_path() / "tessera-store-cost-test";
    farm_.emplace(config_, clock_);
  }

  /// A 64x64 job in 8x8 tiles (64 tiles) of `spp` batches of 1 spp.
  int64_t submit(int64_t spp) {
    v1::JobRequestOptions options;
    options.set_width(64);
    options.set_height(64);
    options.set_tile_size(8);
    options.set_spp(spp);
    options.set_batch_spp(1);
    return farm_->submit(tiny_bundle(), options, 0, "c").id;
  }

  CycleCost cycle(int64_t worker) {
    CycleCost cost;
    const StoreCounters c0 = farm_->store_counters();
    const std::optional<LeasedUnit> unit =
        farm_->lease(worker, std::chrono::milliseconds(0), [] { return false; });
    const StoreCounters c1 = farm_->store_counters();
    EXPECT_TRUE(unit.has_value());
    if (!unit) return cost;
    const uint32_t samples = unit->sample_end - unit->sample_begin;
    UnitResult r = testing::result_for(
        unit->lease, testing::StoreFixture::synthetic(unit->rect, unit->lease.batch, samples));
    EXPECT_TRUE(farm_->upload(r).accepted);
    const StoreCounters c2 = farm_->store_counters();
    cost.lease = minus(c1, c0);
    cost.upload = minus(c2, c1);
    return cost;
  }

  testing::FakeClock clock_;
  CoordinatorConfig config_;
  std::optional<Coordinator> farm_;
};

TEST_F(StoreCost, LeaseAndAcceptUseFewStatementsAndNoneIsCompiledAgain) {
  submit(16);
  const int64_t worker = farm_->register_worker({"w", 4, "avx2", "test"});
  uint64_t lease_statements = 0, upload_statements = 0, reprepares = 0;
  constexpr int kCycles = 200;
  for (int i = 0; i < kCycles; ++i) {
    clock_.advance(1);
    const CycleCost c = cycle(worker);
    lease_statements += c.lease.statements;
    upload_statements += c.upload.statements;
    // The first calls compile the statements; after that none may be compiled again.
    if (i >= 2) reprepares += c.lease.reprepares + c.upload.reprepares;
  }
  const double per_lease = double(lease_statements) / kCycles;
  const double per_upload = double(upload_statements) / kCycles;
  std::printf("statements per lease %.2f, per accepted result %.2f\n", per_lease, per_upload);
  EXPECT_EQ(reprepares, 0u);
  // The lease runs none (server/lease_book.h): its rows are written with the upload's call
  // (FarmStore::flush_leases), so the upload carries them. Before the book: at most 10.5 per
  // lease and 11.5 per accepted result.
  EXPECT_EQ(lease_statements, 0u);
  EXPECT_LE(per_upload, 17.0);  // 16.30 measured (BENCHMARKS.md)
}

// Batched calls: 16 leases in one call, 16 results in one transaction (BEGIN and COMMIT once,
// the job's spec read once per call).
TEST_F(StoreCost, BatchedCallsCostFewerStatementsPerResult) {
  submit(16);
  const int64_t worker = farm_->register_worker({"w", 4, "avx2", "test"});
  uint64_t lease_statements = 0, upload_statements = 0, results = 0;
  for (int call = 0; call < 32; ++call) {
    clock_.advance(1);
    const StoreCounters c0 = farm_->store_counters();
    const std::vector<LeasedUnit> units =
        farm_->lease_units(worker, 16, std::chrono::milliseconds(0), [] { return false; });
    const StoreCounters c1 = farm_->store_counters();
    ASSERT_EQ(units.size(), 16u);
    std::vector<UnitResult> uploads;
    for (const LeasedUnit& u : units) {
      uploads.push_back(testing::result_for(
          u.lease, testing::StoreFixture::synthetic(u.rect, u.lease.batch,
                                                    u.sample_end - u.sample_begin)));
    }
    for (const AcceptOutcome& o : farm_->upload_all(uploads)) EXPECT_TRUE(o.accepted);
    const StoreCounters c2 = farm_->store_counters();
    lease_statements += c1.statements - c0.statements;
    upload_statements += c2.statements - c1.statements;
    results += units.size();
    if (call >= 2) {
      EXPECT_EQ(c2.reprepares - c0.reprepares, 0u);
    }
  }
  const double per_lease = double(lease_statements) / double(results);
  const double per_upload = double(upload_statements) / double(results);
  std::printf("batches of 16: statements per leased unit %.2f, per accepted result %.2f\n",
              per_lease, per_upload);
  // Before the lease book: at most 6.0 per leased unit and 5.25 per accepted result.
  EXPECT_EQ(lease_statements, 0u);
  EXPECT_LE(per_upload, 7.75);  // 7.19 measured (BENCHMARKS.md)
}

TEST_F(StoreCost, RowsVisitedPerCycleDoNotGrowWithTheUnitsDone) {
  // 64 tiles x 40 batches: cycles 20-70 see about 50 unit rows, cycles 1,950-2,000 about 2,000.
  submit(40);
  const int64_t worker = farm_->register_worker({"w", 4, "avx2", "test"});
  auto steps = [&](int from, int to) {
    uint64_t total = 0;
    for (int i = from; i < to; ++i) {
      const CycleCost c = cycle(worker);
      total += c.lease.vm_steps + c.upload.vm_steps;
    }
    return double(total) / double(to - from);
  };
  steps(0, 20);
  const double early = steps(20, 70);
  steps(70, 1950);
  const double late = steps(1950, 2000);
  std::printf("VM steps per lease + upload: %.0f early, %.0f late\n", early, late);
  // A scan of the job's unit rows would make `late` about 40 times `early`.
  EXPECT_LT(late, 1.5 * early);
}

// An idle worker's long poll looks again at every wake-up; its looks, like every lease, are
// answered from the lease book (server/lease_book.h): no statement, no store lock. (Before the
// book, a look cost up to 47 statements with 20 jobs running, and empty looks were reused for
// a second.)
TEST_F(StoreCost, AnIdleWorkersLooksCostNoStatementAndNoStoreLock) {
  submit(1);
  const int64_t busy = farm_->register_worker({"b", 4, "avx2", "test"});
  const int64_t worker = farm_->register_worker({"w", 4, "avx2", "test"});
  const auto look = [&](int64_t w, uint32_t n) {
    return farm_->lease_units(w, n, std::chrono::milliseconds(0), [] { return false; });
  };
  ASSERT_EQ(look(busy, 64).size(), 64u);  // every unit
  const StoreCounters before = farm_->store_counters();
  const uint64_t locks = farm_->store_lock_acquisitions();
  for (int i = 0; i < 10; ++i) {
    clock_.advance(100);
    EXPECT_TRUE(look(worker, 16).empty());
  }
  EXPECT_EQ(farm_->store_lock_acquisitions() - locks, 0u);
  EXPECT_EQ(farm_->store_counters().statements - before.statements, 0u);
}

// Whatever makes a unit leasable reaches the lease book at once: a look right after a submit or
// a release, at the same instant, finds its units.
TEST_F(StoreCost, ALookSeesASubmitAndAReleaseAtOnce) {
  const int64_t worker = farm_->register_worker({"w", 4, "avx2", "test"});
  const int64_t other = farm_->register_worker({"o", 4, "avx2", "test"});
  const auto look = [&](int64_t w, uint32_t n) {
    return farm_->lease_units(w, n, std::chrono::milliseconds(0), [] { return false; });
  };
  EXPECT_TRUE(look(worker, 1).empty());
  submit(1);  // 64 tiles, one unit each
  const std::vector<LeasedUnit> mine = look(worker, 1);
  ASSERT_EQ(mine.size(), 1u);  // the submit is seen at once
  ASSERT_EQ(look(other, 63).size(), 63u);
  const LeasedUnit& u = mine.front();
  ASSERT_TRUE(farm_->upload(testing::result_for(
                                u.lease, testing::StoreFixture::synthetic(
                                             u.rect, u.lease.batch, u.sample_end - u.sample_begin)))
                  .accepted);
  EXPECT_TRUE(look(worker, 1).empty());  // every unit is done or leased to `other`
  const std::vector<LeasedUnit> held = look(other, 63);  // its leases, handed again
  ASSERT_EQ(held.size(), 63u);
  ASSERT_TRUE(farm_->release(other, held.front().lease.lease_id, ReleaseReason::shutdown,
                             "stopping")
                  .released);
  const std::vector<LeasedUnit> back = look(worker, 1);  // the same instant
  ASSERT_EQ(back.size(), 1u);
  EXPECT_EQ(back.front().lease.tile, held.front().lease.tile);
}

// A job's status (six aggregates over its tiles, read for every WatchJob message and status
// call) and a merge's update of its tile touch a few pages whatever the size of the tiles'
// checkpoints, and the status statement is not compiled again on each read. While the checkpoint was a column of the tiles row ahead of error, finished and
// spp, both walked every checkpoint's overflow pages: 16 checkpoints of 120 KB made the status
// read touch 3,477 pages and the tile update 333; now 15 and 2 (migration 10).
TEST(StoreCostOfCheckpoints, StatusAndMergeTouchNoCheckpointPage) {
  testing::StoreFixture f;
  const int64_t job = f.make_job(256, 256, 64, 16, 1);  // 16 tiles of 64x64
  std::mt19937_64 noise(14);
  std::vector<std::string> checkpoints;
  TilesTable tiles(f.db);
  for (uint32_t t = 0; t < 16; ++t) {
    std::string bytes(120'000, '\0');  // a 64x64 tile's encoded sum is 100-150 KB
    for (char& b : bytes) b = char(noise());
    tiles.write_checkpoint(job, t, bytes);
    checkpoints.push_back(std::move(bytes));
  }
  ASSERT_TRUE(f.jobs.get(job).has_value());  // compiles the statement
  StoreCounters before = f.db.counters();
  ASSERT_TRUE(f.jobs.get(job).has_value());
  const uint64_t status_pages = f.db.counters().pages - before.pages;
  // Nor is the status statement compiled again on each read (a bound 'leased' made SQLite
  // re-plan it for the partial indexes on units every time).
  EXPECT_EQ(f.db.counters().reprepares - before.reprepares, 0u);
  before = f.db.counters();
  ASSERT_TRUE(tiles.advance(job, 3, 0, TileProgress{1, 0.5, StopReason::none, 1}));
  const uint64_t advance_pages = f.db.counters().pages - before.pages;
  std::printf("pages touched: status %llu, a merge's tile update %llu\n",
              (unsigned long long)status_pages, (unsigned long long)advance_pages);
  EXPECT_LE(status_pages, 64u);
  EXPECT_LE(advance_pages, 16u);
  // The checkpoints are where they were written, unchanged.
  EXPECT_EQ(tiles.checkpoint(job, 3), checkpoints[3]);
  const std::vector<TileRecord> records = f.jobs.tiles(job);
  ASSERT_EQ(records.size(), 16u);
  for (uint32_t t = 0; t < 16; ++t) EXPECT_EQ(records[t].accumulation, checkpoints[t]) << t;
  EXPECT_EQ(records[3].next_batch, 1u);
  EXPECT_EQ(records[3].spp, 1u);
}

// A tile's merged results are deleted at its checkpoint: about 100 KB each at 64 px, most of
// what a job writes. Debian's SQLite is built with SQLITE_SECURE_DELETE, under which a delete
// zeroed every page of the row's overflow chain and wrote it to the WAL (and the WAL's
// checkpoint into the file) a second time; with secure_delete = FAST (store/sqlite.cpp) the freed
// pages go to the free list unwritten. Counted in WAL frames on a file store: 8 results of
// 100 KB (about 200 pages) cost 200 frames to delete before, 7 now.
TEST(StoreCostOfCheckpoints, DroppingMergedResultsWritesNoFreedPageAgain) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() /
      ("tessera-store-cost-wal-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  {
    testing::StoreFixture f((dir / "store.db").string());
    const int64_t job = f.make_job(64, 64, 64, 8, 1);  // one tile of 64x64, 8 batches
    ResultsTable results(f.db);
    std::mt19937_64 noise(15);
    std::vector<std::string> rows(8, std::string(100'000, '\0'));
    {
      Transaction tx(f.db);
      for (uint32_t b = 0; b < 8; ++b) {
        for (char& c : rows[b]) c = char(noise());  // incompressible, as encoded sums nearly are
        results.append(job, 0, b, rows[b]);
      }
      tx.commit();
    }
    ASSERT_TRUE(checkpoint_wal(f.db));  // everything in the file, the WAL empty
    {
      Transaction tx(f.db);
      EXPECT_EQ(results.drop_merged(job, 0, 8), 8);
      tx.commit();
    }
    auto q = f.db.prepare("PRAGMA wal_checkpoint(PASSIVE)");
    ASSERT_TRUE(q->step());
    const int64_t frames = q->int64(1);  // pages the delete wrote to the WAL
    std::printf("WAL frames written by deleting 8 results of 100 KB: %lld\n", (long long)frames);
    EXPECT_GT(frames, 0);
    EXPECT_LE(frames, 16);
    EXPECT_EQ(results.count(job), 0);
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace tessera::server
