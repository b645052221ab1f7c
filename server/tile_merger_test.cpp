// Accepting results: the compare-and-set on the lease id, and the in-order merge per tile.
#include <gtest/gtest.h>

#include <bit>
#include <filesystem>
#include <unistd.h>

#include "accum/accumulation_codec.h"
#include "accum/film.h"
#include "farm_error.h"
#include "store_fixture.h"

namespace tessera::server {
namespace {

using testing::StoreFixture;
using testing::result_for;

/// Leases (tile, batch) for `worker` (which must hold no lease): helpers lease the units that
/// the scheduler orders before it, the worker takes it, then the helpers hand theirs back.
Lease lease_unit(StoreFixture& f, int64_t worker, uint32_t tile, uint32_t batch) {
  std::vector<Lease> blockers;
  for (;;) {
    const std::optional<Lease> l = f.book.lease_next(f.make_worker("helper"));
    if (!l) {
      ADD_FAILURE() << "unit tile " << tile << " batch " << batch << " is not queued";
      return {};
    }
    if (l->tile == tile && l->batch == batch) {
      f.leases.release(l->worker_id, l->lease_id, ReleaseReason::shutdown, "");
      break;
    }
    blockers.push_back(*l);
  }
  const Lease got = *f.book.lease_next(worker);
  EXPECT_EQ(got.tile, tile);
  EXPECT_EQ(got.batch, batch);
  for (const Lease& b : blockers) {
    f.leases.release(b.worker_id, b.lease_id, ReleaseReason::shutdown, "");
  }
  return got;
}

Accumulation tile_sum(StoreFixture& f, int64_t job, uint32_t tile) {
  const std::vector<TileRecord> tiles = f.tiles(job);
  return decode_accumulation(tiles.at(tile).accumulation);
}

constexpr TileRect kTile{0, 0, 4, 4};

TEST(TileMerger, ResultsArriving201MergeAs012) {
  StoreFixture f;
  const int64_t job = f.make_job(4, 4, 4, 3, 1);  // one tile, 3 batches of 1 spp
  const int64_t w = f.make_worker();
  std::vector<Accumulation> batch;
  for (uint32_t b = 0; b < 3; ++b) batch.push_back(StoreFixture::synthetic(kTile, b, 1));

  const Lease l2 = lease_unit(f, w, 0, 2);
  AcceptOutcome o = f.merger.accept(result_for(l2, batch[2]), batch[2]);
  EXPECT_TRUE(o.accepted);
  EXPECT_EQ(o.merged, 0u);  // waits for 0 and 1
  EXPECT_EQ(f.tiles(job)[0].next_batch, 0u);
  EXPECT_EQ(f.jobs.get(job)->counters.units_done, 1u);
  EXPECT_EQ(f.jobs.get(job)->counters.results_merged, 0u);

  const Lease l0 = lease_unit(f, w, 0, 0);
  o = f.merger.accept(result_for(l0, batch[0]), batch[0]);
  EXPECT_EQ(o.merged, 1u);  // 0 only: 1 is missing
  EXPECT_EQ(f.tiles(job)[0].next_batch, 1u);
  EXPECT_EQ(f.jobs.get(job)->spp_merged, 1u);

  const Lease l1 = lease_unit(f, w, 0, 1);
  o = f.merger.accept(result_for(l1, batch[1]), batch[1]);
  EXPECT_EQ(o.merged, 2u);  // 1, then the waiting 2
  EXPECT_TRUE(o.job_complete);

  // Exactly zeros + 0 + 1 + 2, as `tessera-worker render` sums them.
  Accumulation expected(kTile);
  for (const Accumulation& a : batch) expected.merge(a);
  EXPECT_EQ(tile_sum(f, job, 0), expected);
  // And the order matters for these values: 2, 0, 1 would give other bits.
  Accumulation arrival_order(kTile);
  for (int b : {2, 0, 1}) arrival_order.merge(batch[size_t(b)]);
  EXPECT_NE(arrival_order.rgb, expected.rgb);

  const JobRecord done = *f.jobs.get(job);
  EXPECT_EQ(done.counters.results_merged, 3u);
  EXPECT_EQ(done.counters.units_done, 3u);
  EXPECT_EQ(done.spp_merged, 3u);
  EXPECT_EQ(done.progress(), 1.0);
  EXPECT_EQ(done.counters.samples_merged, 16u * 3u);
  EXPECT_EQ(done.isas, std::vector<std::string>{"avx2"});
  auto q = f.db.prepare("SELECT COUNT(*) FROM results");
  ASSERT_TRUE(q->step());
  EXPECT_EQ(q->int64(0), 0);
}

// The tile's stored error is computed where the rule reads it (noise tiles from 16 spp on), at
// checkpoints and when the tile's spp reaches a power of two, not after every merged batch: in
// between the tile keeps the value stored last (server/tile_merger.cpp). Merging every batch
// and computing it each time would store the error at 3 spp below.
TEST(TileMerger, TheErrorIsComputedOnlyWhereReadOrStored) {
  StoreFixture f;
  const int64_t job = f.make_job(4, 4, 4, 10, 1);  // one tile, 10 batches of 1 spp (spp rule)
  const int64_t w = f.make_worker();
  const auto stored_error = [&] {
    auto q = f.db.prepare("SELECT error FROM tiles WHERE job_id = ? AND tile = 0");
    q->bind(1, job);
    EXPECT_TRUE(q->step());
    return q->real(0);
  };
  Accumulation sum(kTile);
  std::vector<double> error_at;  // error_at[n]: the estimate after n merged batches
  error_at.push_back(0);
  int kept_older = 0;  // merges after which the stored error was an older estimate
  for (uint32_t b = 0; b < 10; ++b) {
    const Accumulation batch = StoreFixture::synthetic(kTile, b, 1);
    const Lease l = *f.book.lease_next(w);
    ASSERT_EQ(l.batch, b);
    ASSERT_TRUE(f.merger.accept(result_for(l, batch), batch).accepted);
    sum.merge(batch);
    error_at.push_back(estimate_relative_error(sum));
    const uint32_t n = b + 1;  // batches merged = spp
    // Stored at 1, 2, 4, 8 spp (powers of two; 8 is also the first checkpoint) and at 10 (the
    // tile ends); at 3 the value of 2, at 5-7 the value of 4, at 9 the value of 8.
    const uint32_t last_stored = n == 10 ? 10 : std::bit_floor(n);
    EXPECT_EQ(stored_error(), error_at[last_stored]) << "after " << n << " batches";
    if (error_at[n] != error_at[last_stored]) ++kept_older;
  }
  // The test means something only where the estimate changed in between: at 3 spp at least.
  EXPECT_NE(error_at[3], error_at[2]);
  EXPECT_GE(kept_older, 1);
  EXPECT_EQ(f.tiles(job)[0].finished, StopReason::spp_reached);
}

// A merge looks for the next batch in the store only where a waiting row may be missing from
// memory (TileMerger::may_wait_in_store). A transaction that took a waiting result from memory
// and then rolled back leaves that row waiting in the store only: the next merge must still
// find it there. Without the rollback's mark the tile would stop at batch 2 for good, with
// batch 2 accepted and never merged.
TEST(TileMerger, AWaitingResultTakenByARolledBackTransactionIsStillMerged) {
  StoreFixture f;
  const int64_t job = f.make_job(8, 4, 4, 4, 1);  // two tiles, 4 batches of 1 spp
  const int64_t w = f.make_worker("w"), other = f.make_worker("other");
  std::vector<Accumulation> batch;
  for (uint32_t b = 0; b < 4; ++b) batch.push_back(StoreFixture::synthetic(kTile, b, 1));

  const Lease l0 = lease_unit(f, w, 0, 0);
  ASSERT_EQ(f.merger.accept(result_for(l0, batch[0]), batch[0]).merged, 1u);
  const Lease l2 = lease_unit(f, w, 0, 2);
  ASSERT_EQ(f.merger.accept(result_for(l2, batch[2]), batch[2]).merged, 0u);  // waits for 1

  // One transaction: batch 1 of tile 0 (merges 1, then the waiting 2 from memory) and a result
  // for tile 1 that does not cover its tile: the whole call is refused and rolled back.
  const Lease l1 = lease_unit(f, w, 0, 1);
  const Lease bad_lease = lease_unit(f, other, 1, 0);
  const UnitResult r1 = result_for(l1, batch[1]);
  Accumulation acc1 = batch[1];
  Accumulation wrong = StoreFixture::synthetic(kTile, 0, 1);  // tile 0's rectangle, not tile 1's
  const UnitResult bad = result_for(bad_lease, wrong);
  EXPECT_THROW(f.merger.accept_all({{&r1, &acc1}, {&bad, &wrong}}), FarmError);
  EXPECT_EQ(f.tiles(job)[0].next_batch, 1u);

  // The lease of batch 1 is still current: delivered again, it merges 1 and then 2, which is
  // now in the store only.
  const AcceptOutcome again = f.merger.accept(r1, batch[1]);
  EXPECT_TRUE(again.accepted);
  EXPECT_EQ(again.merged, 2u);
  EXPECT_EQ(f.tiles(job)[0].next_batch, 3u);
}

// An upload group ends its transaction between two calls when a lease waits for the store
// (ResultIntake::commit_uploads): accept_calls asks `stop` after each call but the last, commits
// the calls so far, and leaves the others' leases current for the next transaction.
TEST(TileMerger, AcceptCallsStopsBetweenCallsAndLeavesTheOthersForTheNextTransaction) {
  StoreFixture f;
  const int64_t job = f.make_job(8, 4, 4, 4, 1);  // two tiles, 4 batches of 1 spp
  // (A worker holds one lease at a time here: one worker per unit.)
  const int64_t w = f.make_worker("w"), w1 = f.make_worker("w1"), v = f.make_worker("v");
  const Accumulation b0 = StoreFixture::synthetic(kTile, 0, 1);
  const Accumulation b1 = StoreFixture::synthetic(kTile, 1, 1);
  const Accumulation t1 = StoreFixture::synthetic(TileRect{4, 0, 8, 4}, 0, 1);
  const Lease l0 = lease_unit(f, w, 0, 0), l1 = lease_unit(f, w1, 0, 1);
  const Lease m0 = lease_unit(f, v, 1, 0);
  const UnitResult r0 = result_for(l0, b0), r1 = result_for(l1, b1), s0 = result_for(m0, t1);
  Accumulation a0 = b0, a1 = b1, c0 = t1;
  // Two calls: two results of tile 0, then one of tile 1.
  const std::vector<TileMerger::Upload> uploads{{&r0, &a0}, {&r1, &a1}, {&s0, &c0}};
  int asked = 0;
  const std::vector<AcceptOutcome> first =
      f.merger.accept_calls(uploads, {2, 3}, [&] { return ++asked > 0; });
  EXPECT_EQ(asked, 1);  // after the first call only, never after the last
  ASSERT_EQ(first.size(), 2u);  // the whole first call, nothing of the second
  EXPECT_TRUE(first[0].accepted && first[1].accepted);
  EXPECT_EQ(f.tiles(job)[0].next_batch, 2u);
  EXPECT_EQ(f.tiles(job)[1].next_batch, 0u);  // v's result untouched: its lease still current
  // The rest, in the next transaction: accepted exactly as it would have been.
  const std::vector<AcceptOutcome> rest =
      f.merger.accept_calls({uploads[2]}, {1}, [&] { return ++asked > 0; });
  ASSERT_EQ(rest.size(), 1u);
  EXPECT_TRUE(rest[0].accepted);
  EXPECT_EQ(rest[0].merged, 1u);
  EXPECT_EQ(asked, 1);  // a single call: nothing to stop between
  EXPECT_EQ(f.tiles(job)[1].next_batch, 1u);

  // Not stopped: every call in one transaction.
  const Lease l2 = lease_unit(f, f.make_worker("w2"), 0, 2);
  const Lease m1 = lease_unit(f, f.make_worker("v1"), 1, 1);
  const Accumulation b2 = StoreFixture::synthetic(kTile, 2, 1);
  const Accumulation t1b = StoreFixture::synthetic(TileRect{4, 0, 8, 4}, 1, 1);
  const UnitResult r2 = result_for(l2, b2), s1 = result_for(m1, t1b);
  Accumulation a2 = b2, c1 = t1b;
  const std::vector<AcceptOutcome> all =
      f.merger.accept_calls({{&r2, &a2}, {&s1, &c1}}, {1, 2}, [] { return false; });
  EXPECT_EQ(all.size(), 2u);
  EXPECT_EQ(f.tiles(job)[0].next_batch, 3u);
  EXPECT_EQ(f.tiles(job)[1].next_batch, 2u);
}

TEST(TileMerger, StaleLeaseResultIsDroppedAndCounted) {
  StoreFixture f;
  const int64_t job = f.make_job(4, 4, 4, 1, 1);
  const int64_t slow = f.make_worker("slow"), fast = f.make_worker("fast");
  const Lease stale = *f.book.lease_next(slow);
  f.clock.advance(StoreFixture::kLeaseMs + 1);
  ASSERT_EQ(f.book.expire_due(), 1);
  const Lease current = *f.book.lease_next(fast);
  ASSERT_EQ(current.unit_id, stale.unit_id);

  const Accumulation acc = StoreFixture::synthetic(kTile, 0, 1);
  const AcceptOutcome late = f.merger.accept(result_for(stale, acc), acc);
  EXPECT_FALSE(late.accepted);
  EXPECT_NE(late.reason.find("not the current lease"), std::string::npos);
  EXPECT_EQ(f.jobs.get(job)->counters.results_dropped, 1u);
  EXPECT_EQ(f.jobs.get(job)->counters.units_done, 0u);
  EXPECT_EQ(f.tiles(job)[0].next_batch, 0u);

  EXPECT_TRUE(f.merger.accept(result_for(current, acc), acc).accepted);
  // A duplicate delivery of the accepted result is dropped too.
  EXPECT_FALSE(f.merger.accept(result_for(current, acc), acc).accepted);
  const JobRecord j = *f.jobs.get(job);
  EXPECT_EQ(j.counters.results_dropped, 2u);
  EXPECT_EQ(j.counters.units_done, 1u);
  EXPECT_EQ(j.counters.results_merged, 1u);
  EXPECT_EQ(tile_sum(f, job, 0).count[0], 1u);  // merged once
}

TEST(TileMerger, AnotherWorkersLeaseIdIsNotEnough) {
  StoreFixture f;
  f.make_job(4, 4, 4, 1, 1);
  const int64_t owner = f.make_worker("owner"), thief = f.make_worker("thief");
  Lease lease = *f.book.lease_next(owner);
  const Accumulation acc = StoreFixture::synthetic(kTile, 0, 1);
  lease.worker_id = thief;
  EXPECT_FALSE(f.merger.accept(result_for(lease, acc), acc).accepted);
  EXPECT_TRUE(f.book.heartbeat(owner, lease.lease_id));
}

TEST(TileMerger, ResultsOfACancelledJobAreDropped) {
  StoreFixture f;
  const int64_t job = f.make_job(4, 4, 4, 1, 1);
  const int64_t worker = f.make_worker();
  const Lease lease = *f.book.lease_next(worker);
  f.jobs.cancel(job, 0);
  const Accumulation acc = StoreFixture::synthetic(kTile, 0, 1);
  EXPECT_FALSE(f.merger.accept(result_for(lease, acc), acc).accepted);
  EXPECT_EQ(f.jobs.get(job)->counters.results_dropped, 1u);
  EXPECT_EQ(f.jobs.get(job)->state, JobState::cancelled);
  // The user cancelled, the worker did not fail: nothing counts against it.
  EXPECT_EQ(f.workers.get(worker)->units_lost, 0u);
}

TEST(TileMerger, RefusesAResultThatDoesNotFitTheUnit) {
  StoreFixture f;
  const int64_t job = f.make_job(8, 4, 4, 2, 2);
  const Lease lease = *f.book.lease_next(f.make_worker());
  ASSERT_EQ(lease.tile, 0u);
  const Accumulation wrong_tile = StoreFixture::synthetic({4, 0, 8, 4}, 0, 2);
  try {
    f.merger.accept(result_for(lease, wrong_tile), wrong_tile);
    FAIL() << "a result for another tile was accepted";
  } catch (const FarmError& e) {
    EXPECT_EQ(e.code(), ErrorCode::invalid_argument);
  }
  const Accumulation too_many = StoreFixture::synthetic(kTile, 0, 3);  // the batch has 2 spp
  EXPECT_THROW(f.merger.accept(result_for(lease, too_many), too_many), FarmError);
  // Nothing changed: the lease is still current and a good result is accepted.
  EXPECT_EQ(f.jobs.get(job)->counters.units_done, 0u);
  EXPECT_EQ(f.jobs.get(job)->counters.results_dropped, 0u);
  const Accumulation good = StoreFixture::synthetic(kTile, 0, 2);
  EXPECT_TRUE(f.merger.accept(result_for(lease, good), good).accepted);
}

TEST(TileMerger, UnknownUnitIsNotFound) {
  StoreFixture f;
  f.make_job(4, 4, 4, 1, 1);
  Lease lease = *f.book.lease_next(f.make_worker());
  lease.batch = 7;
  const Accumulation acc = StoreFixture::synthetic(kTile, 0, 1);
  try {
    f.merger.accept(result_for(lease, acc), acc);
    FAIL();
  } catch (const FarmError& e) {
    EXPECT_EQ(e.code(), ErrorCode::not_found);
  }
}

TEST(TileMerger, PendingResultsSurviveARestart) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("tessera-merge-test-" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "restart.db").string();
  std::filesystem::remove(path);
  std::vector<Accumulation> batch;
  for (uint32_t b = 0; b < 3; ++b) batch.push_back(StoreFixture::synthetic(kTile, b, 1));
  int64_t job = 0;
  {
    testing::FakeClock clock;
    Database db(path);
    migrate(db, clock.now_unix_ms());
    JobStore jobs(db);
    WorkerRegistry workers(db);
    LeaseTable leases(db, jobs, clock, 1000);
    testing::BookLeaser scheduler(db, jobs, leases, clock);
    TileMerger merger(db, clock);
    NewJob nj;
    nj.bundle_sha256 = std::string(64, 'e');
    nj.scene_file = "s.json";
    nj.bundle_bytes = "b";
    nj.options.width = nj.options.height = nj.options.tile_size = 4;
    nj.options.spp = 3;
    nj.options.batch_spp = 1;
    job = jobs.create(nj, 0);
    std::vector<Lease> held;
    for (int i = 0; i < 3; ++i) {
      held.push_back(*scheduler.lease_next(workers.register_worker({"w", 1, "", ""}, 0)));
    }
    // Batch 2 arrives first and waits; then the "server" dies with 0 and 1 still leased.
    ASSERT_EQ(held[2].batch, 2u);
    UnitResult r = result_for(held[2], batch[2]);
    ASSERT_TRUE(merger.accept(r, batch[2]).accepted);
  }
  {
    testing::FakeClock clock;
    Database db(path);
    migrate(db, clock.now_unix_ms());
    JobStore jobs(db);
    WorkerRegistry workers(db);
    LeaseTable leases(db, jobs, clock, 1000);
    testing::BookLeaser scheduler(db, jobs, leases, clock);
    TileMerger merger(db, clock);
    EXPECT_EQ(leases.revoke_all(), 2);  // what the server does at start
    const int64_t w = workers.register_worker({"after", 1, "", ""}, 0);
    for (uint32_t b : {0u, 1u}) {
      const Lease l = *scheduler.lease_next(w);
      ASSERT_EQ(l.batch, b);
      ASSERT_TRUE(merger.accept(result_for(l, batch[b]), batch[b]).accepted);
    }
    const JobRecord done = *jobs.get(job);
    EXPECT_EQ(done.counters.results_merged, 3u);
    EXPECT_EQ(done.counters.units_done, 3u);
    Accumulation expected(kTile);
    for (const Accumulation& a : batch) expected.merge(a);
    EXPECT_EQ(decode_accumulation(jobs.tiles(job)[0].accumulation), expected);
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace tessera::server
