// The stopping rules in the store: the time budget against a fake clock, the noise rule's
// per-tile decisions and lookahead, migration 2, and the indexed lease query.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "accum/accumulation_codec.h"
#include "store/tile_queue.h"
#include "store/units_table.h"
#include "store_fixture.h"

namespace tessera::server {
namespace {

using testing::StoreFixture;
using testing::result_for;

/// A job of `tiles` 4x4 tiles in a row with the given rule; batch 16 spp.
int64_t make_rule_job(StoreFixture& f, StopRule rule, uint32_t tiles, uint32_t spp,
                      double budget_s = 0, double noise = 0) {
  NewJob job;
  job.scene_file = "scene.json";
  job.bundle_bytes = "bundle of job " + std::to_string(++f.job_counter);
  job.bundle_sha256 = std::string(63, 'b') + std::to_string(f.job_counter % 10);
  job.options.width = int(4 * tiles);
  job.options.height = 4;
  job.options.tile_size = 4;
  job.options.spp = spp;
  job.options.batch_spp = 16;
  job.options.rule = rule;
  job.options.time_budget_s = budget_s;
  job.options.noise_target = noise;
  return f.jobs.create(job, f.clock.now_unix_ms());
}

/// 16 samples per pixel of constant grey `v`: zero variance, error 0.
Accumulation smooth(const TileRect& rect, double v = 0.5) {
  Accumulation acc(rect);
  for (size_t i = 0; i < acc.pixels(); ++i) {
    for (int c = 0; c < 3; ++c) acc.rgb[i * 3 + c] = 16 * v;
    acc.lum2[i] = 16 * v * v;
    acc.count[i] = 16;
  }
  return acc;
}

/// 16 samples per pixel, half 0 and half 1 (grey): relative error sqrt(1/60)/0.5, about 0.26 at
/// 16 spp, and still far above 0.02 at the caps used here.
Accumulation noisy(const TileRect& rect) {
  Accumulation acc(rect);
  for (size_t i = 0; i < acc.pixels(); ++i) {
    for (int c = 0; c < 3; ++c) acc.rgb[i * 3 + c] = 8;
    acc.lum2[i] = 8;
    acc.count[i] = 16;
  }
  return acc;
}

TileRect rect_of(uint32_t tile) { return {int(4 * tile), 0, int(4 * tile + 4), 4}; }

TEST(TimeRule, NoLeaseAfterTheBudgetInFlightUnitsAreAwaited) {
  StoreFixture f;
  const int64_t job = make_rule_job(f, StopRule::time, 2, 64, /*budget_s=*/5);  // 2 x 4 units
  const Lease first = *f.book.lease_next(f.make_worker("a"));  // the budget starts here
  f.clock.advance(4'999);
  const Lease second = *f.book.lease_next(f.make_worker("b"));
  EXPECT_TRUE(f.leases.enforce_time_budgets().empty());
  f.clock.advance(1);  // exactly at the budget
  EXPECT_EQ(f.book.lease_next(f.make_worker("c")), std::nullopt);
  // The bookkeeping skips the queued units; the two in flight keep the job open.
  EXPECT_TRUE(f.leases.enforce_time_budgets().empty());
  JobRecord r = *f.jobs.get(job);
  EXPECT_EQ(r.counters.units_skipped, 6u);
  EXPECT_EQ(r.budget_reached_unix_ms, f.clock.now_unix_ms());
  EXPECT_FALSE(r.complete);
  // They come back after the budget and still merge.
  EXPECT_TRUE(
      f.merger.accept(result_for(first, smooth(rect_of(first.tile))), smooth(rect_of(first.tile)))
          .accepted);
  const AcceptOutcome last = f.merger.accept(result_for(second, smooth(rect_of(second.tile))),
                                             smooth(rect_of(second.tile)));
  EXPECT_TRUE(last.accepted);
  EXPECT_TRUE(last.job_complete);
  EXPECT_EQ(f.jobs.settle(job), StopReason::time_budget);
  r = *f.jobs.get(job);
  EXPECT_EQ(r.stop_reason, StopReason::time_budget);
  EXPECT_EQ(r.reached.spp_min, 16u);
  EXPECT_EQ(r.reached.spp_max, 16u);
  EXPECT_TRUE(f.jobs.finish(job, "a.exr", "a.png", f.clock.now_unix_ms()));
  EXPECT_EQ(f.jobs.get(job)->state, JobState::done);
}

TEST(TimeRule, BudgetCountsFromTheFirstLeaseNotFromSubmission) {
  StoreFixture f;
  make_rule_job(f, StopRule::time, 1, 64, 5);
  f.clock.advance(60'000);  // queued for a minute: not part of the budget
  EXPECT_TRUE(f.book.lease_next(f.make_worker()));
  f.clock.advance(4'000);
  EXPECT_TRUE(f.book.lease_next(f.make_worker("b")));
}

TEST(TimeRule, AnExpiredLeaseAfterTheBudgetIsSkippedAndTheJobFinishes) {
  StoreFixture f;
  const int64_t job = make_rule_job(f, StopRule::time, 1, 32, 1);  // 1 tile x 2 batches
  const Lease l0 = *f.book.lease_next(f.make_worker());
  const Lease l1 = *f.book.lease_next(f.make_worker("b"));
  EXPECT_EQ(l1.batch, 1u);
  f.clock.advance(1'000);
  EXPECT_TRUE(f.leases.enforce_time_budgets().empty());  // both in flight
  f.clock.advance(StoreFixture::kLeaseMs + 1);
  EXPECT_EQ(f.book.expire_due(), 2);                                       // back to queued ...
  EXPECT_EQ(f.leases.enforce_time_budgets(), std::vector<int64_t>{});     // batch 0 kept
  EXPECT_EQ(f.jobs.get(job)->counters.units_skipped, 1u);                    // batch 1 skipped
  EXPECT_FALSE(f.merger.accept(result_for(l1, smooth(rect_of(0))), smooth(rect_of(0))).accepted);
  // Batch 0 is leased again after the budget: a time job never leaves a tile black.
  const Lease again = *f.book.lease_next(f.make_worker("c"));
  EXPECT_EQ(again.batch, 0u);
  EXPECT_FALSE(f.merger.accept(result_for(l0, smooth(rect_of(0))), smooth(rect_of(0))).accepted);
  EXPECT_EQ(f.book.lease_next(f.make_worker("d")), std::nullopt);
  EXPECT_TRUE(
      f.merger.accept(result_for(again, smooth(rect_of(0))), smooth(rect_of(0))).job_complete);
  EXPECT_EQ(f.jobs.settle(job), StopReason::time_budget);
  EXPECT_EQ(f.jobs.get(job)->reached.spp_max, 16u);
}

// The rule on a fake clock: past the budget, batch 0 of every tile is still leased and merged;
// no later batch starts.
TEST(TimeRule, BatchZeroOfEveryTileCompletesNothingStartsAfterTheBudget) {
  StoreFixture f;
  const uint32_t tiles = 5;
  const int64_t job = make_rule_job(f, StopRule::time, tiles, 64, /*budget_s=*/2);
  const int64_t w = f.make_worker("only");
  // One worker, one unit at a time; the first unit alone takes longer than the budget.
  const Lease first = *f.book.lease_next(w);
  f.clock.advance(3'000);
  EXPECT_TRUE(f.merger.accept(result_for(first, smooth(rect_of(first.tile))),
                              smooth(rect_of(first.tile)))
                  .accepted);
  EXPECT_TRUE(f.leases.enforce_time_budgets().empty());
  std::vector<uint32_t> leased_tiles{first.tile};
  for (;;) {
    const std::optional<Lease> l = f.book.lease_next(w);
    if (!l) break;
    EXPECT_EQ(l->batch, 0u) << "a batch started after the budget";
    leased_tiles.push_back(l->tile);
    f.clock.advance(1'000);
    f.merger.accept(result_for(*l, smooth(rect_of(l->tile))), smooth(rect_of(l->tile)));
    f.leases.enforce_time_budgets();
  }
  EXPECT_EQ(leased_tiles.size(), tiles);
  EXPECT_TRUE(f.jobs.get(job)->complete);
  EXPECT_EQ(f.jobs.settle(job), StopReason::time_budget);
  const JobRecord r = *f.jobs.get(job);
  EXPECT_EQ(r.reached.spp_min, 16u);  // every tile has its batch 0
  EXPECT_EQ(r.counters.units_skipped, tiles * 3);
}

TEST(TimeRule, AJobDoneBeforeItsBudgetReportsTheCap) {
  StoreFixture f;
  const int64_t job = make_rule_job(f, StopRule::time, 1, 16, 100);  // one unit
  const Lease l = *f.book.lease_next(f.make_worker());
  EXPECT_TRUE(f.merger.accept(result_for(l, smooth(rect_of(0))), smooth(rect_of(0))).job_complete);
  EXPECT_EQ(f.jobs.settle(job), StopReason::max_spp);
}

TEST(NoiseRule, LeasesAtMostTwoBatchesAheadOfTheMergedPrefix) {
  StoreFixture f;
  make_rule_job(f, StopRule::noise, 2, 256, 0, 0.02);  // 2 tiles x 16 batches
  std::vector<std::pair<uint32_t, uint32_t>> order;
  std::vector<Lease> held;
  for (;;) {
    const std::optional<Lease> l = f.book.lease_next(f.make_worker());
    if (!l) break;
    order.emplace_back(l->batch, l->tile);
    held.push_back(*l);
  }
  EXPECT_EQ(order, (std::vector<std::pair<uint32_t, uint32_t>>{{0, 0}, {0, 1}, {1, 0}, {1, 1}}));
  // Merging tile 0's batch 0 (noisy: not finished) opens its batch 2.
  const Accumulation n0 = noisy(rect_of(0));
  EXPECT_TRUE(f.merger.accept(result_for(held[0], n0), n0).accepted);
  const Lease next = *f.book.lease_next(f.make_worker());
  EXPECT_EQ(next.tile, 0u);
  EXPECT_EQ(next.batch, 2u);
}

TEST(NoiseRule, ATileMeetingItsTargetStopsAndWastesOnlySpeculation) {
  StoreFixture f;
  const int64_t job = make_rule_job(f, StopRule::noise, 2, 64, 0, 0.02);  // 2 tiles x 4 batches
  std::vector<Lease> held;
  for (int i = 0; i < 4; ++i) held.push_back(*f.book.lease_next(f.make_worker()));
  // held: (t0,b0) (t1,b0) (t0,b1) (t1,b1). Tile 0's batch 1 arrives first and waits.
  const Accumulation s0 = smooth(rect_of(0));
  EXPECT_TRUE(f.merger.accept(result_for(held[2], s0), s0).accepted);
  // Batch 0 merges; 16 spp with error 0 <= 0.02: the tile is finished, batch 1 is wasted.
  EXPECT_TRUE(f.merger.accept(result_for(held[0], s0), s0).accepted);
  JobRecord r = *f.jobs.get(job);
  EXPECT_EQ(r.counters.results_wasted, 1u);
  EXPECT_EQ(r.counters.units_skipped, 2u);  // tile 0's batches 2 and 3
  EXPECT_EQ(r.tiles_finished, 1u);
  EXPECT_EQ(f.tiles(job)[0].next_batch, 1u);
  EXPECT_EQ(f.tiles(job)[0].finished, StopReason::noise_target);
  // Tile 1 stays noisy and runs to the cap.
  const Accumulation n1 = noisy(rect_of(1));
  EXPECT_TRUE(f.merger.accept(result_for(held[1], n1), n1).accepted);
  EXPECT_TRUE(f.merger.accept(result_for(held[3], n1), n1).accepted);
  AcceptOutcome last;
  for (;;) {
    const std::optional<Lease> l = f.book.lease_next(f.make_worker());
    if (!l) break;
    EXPECT_EQ(l->tile, 1u);
    last = f.merger.accept(result_for(*l, n1), n1);
  }
  EXPECT_TRUE(last.job_complete);
  EXPECT_EQ(f.jobs.settle(job), StopReason::max_spp);
  r = *f.jobs.get(job);
  EXPECT_EQ(r.reached.spp_min, 16u);
  EXPECT_EQ(r.reached.spp_max, 64u);
  EXPECT_EQ(r.reached.spp_mean, 40.0);
  EXPECT_GT(r.reached.error_max, 0.02);
  EXPECT_EQ(r.counters.samples_merged, uint64_t(16 * 16 + 16 * 64));
}

TEST(NoiseRule, ALeasedUnitOfAFinishedTileIsDroppedWhenItReturns) {
  StoreFixture f;
  const int64_t job = make_rule_job(f, StopRule::noise, 1, 64, 0, 0.02);
  const Lease b0 = *f.book.lease_next(f.make_worker());
  const Lease b1 = *f.book.lease_next(f.make_worker());
  const Accumulation s0 = smooth(rect_of(0));
  EXPECT_TRUE(f.merger.accept(result_for(b0, s0), s0).job_complete);
  const AcceptOutcome late = f.merger.accept(result_for(b1, s0), s0);
  EXPECT_FALSE(late.accepted);
  EXPECT_EQ(f.jobs.get(job)->counters.results_dropped, 1u);
  EXPECT_EQ(f.jobs.settle(job), StopReason::noise_target);
}

TEST(NoiseRule, MergedBatchesDoNotDependOnArrivalOrder) {
  // Same results, two arrival orders: the tile's merged bytes and next_batch are identical.
  std::vector<std::string> merged;
  for (bool reversed : {false, true}) {
    StoreFixture f;
    const int64_t job = make_rule_job(f, StopRule::noise, 1, 64, 0, 0.3);
    std::vector<Lease> held;
    for (int i = 0; i < 2; ++i) held.push_back(*f.book.lease_next(f.make_worker()));
    // Error 0.26 at 16 spp is under the 0.3 target: the tile finishes at batch 0, and batch 1
    // is wasted whether it arrived before or after.
    const Accumulation n = noisy(rect_of(0));
    if (reversed) {
      f.merger.accept(result_for(held[1], n), n);
      f.merger.accept(result_for(held[0], n), n);
    } else {
      f.merger.accept(result_for(held[0], n), n);
      f.merger.accept(result_for(held[1], n), n);
    }
    const TileRecord t = f.tiles(job)[0];
    EXPECT_EQ(t.next_batch, 1u);
    merged.push_back(t.accumulation);
  }
  EXPECT_EQ(merged[0], merged[1]);
}

TEST(Migration2, UpgradesAVersion1StoreKeepingItsJobs) {
  Database db(":memory:");
  schema_version(db);
  const Migration& v1 = schema_migrations().at(0);
  db.exec(v1.sql);
  db.exec("INSERT INTO schema_migrations VALUES (1, 'v1', 0)");
  db.exec(
      "INSERT INTO bundles VALUES ('" + std::string(64, 'c') +
      "', 's.json', x'00', 1, 0);"
      "INSERT INTO jobs (state, priority, bundle_sha256, scene_file, width, height, spp,"
      " max_depth, seed, tile_size, batch_spp, isa, tile_count, batch_count, units_total,"
      " submitted_unix_ms) VALUES ('done', 0, '" +
      std::string(64, 'c') +
      "', 's.json', 8, 8, 4, -1, 0, 8, 4, '', 1, 1, 1, 0);"
      "INSERT INTO tiles (job_id, tile, x0, y0, x1, y1, next_batch) VALUES (1, 0, 0, 0, 8, 8, 1);");
  EXPECT_EQ(migrate(db, 5), schema_migrations().back().version);  // 2 and later applied
  JobStore jobs(db);
  const JobRecord r = *jobs.get(1);
  EXPECT_EQ(r.options.rule, StopRule::spp);
  EXPECT_EQ(r.stop_reason, StopReason::none);
  EXPECT_EQ(r.reached.spp_max, 4u);
  EXPECT_EQ(jobs.tiles(1).at(0).finished, StopReason::none);
}

// Start-up revokes the last run's leases by the partial index on leased units: it reads no
// other unit row (start-up stays fast whatever the store holds).
TEST(SchedulerQuery, RevokingLeasesReadsTheLeasedUnitsAlone) {
  StoreFixture f;
  auto q = f.db.prepare(
      "EXPLAIN QUERY PLAN SELECT id, job_id, worker_id, lease_id FROM units INDEXED BY"
      " units_expiry WHERE state = 'leased' AND lease_expires_unix_ms < ?1");
  q->bind(1, int64_t(1));
  std::string plan;
  while (q->step()) plan += q->text(3) + "\n";
  EXPECT_NE(plan.find("units_expiry"), std::string::npos) << plan;
  EXPECT_EQ(f.leases.revoke_all(), 0);  // and the statement prepares against the real schema
}

}  // namespace
}  // namespace tessera::server
