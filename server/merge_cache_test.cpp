// The merge cache (server/merge_cache.h) and the merger's checkpoints (migration 7): a tile's
// sum in memory, in the store as checkpoint + merged results, bit-identical whichever way it is
// rebuilt, with memory bounded by the budget.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <random>

#include "accum/accumulation_codec.h"
#include "farm_error.h"
#include "store_fixture.h"

namespace tessera::server {
namespace {

using testing::StoreFixture;
using testing::result_for;

MergeCache::Tile tile_of(int pixels, uint32_t next_batch) {
  return {Accumulation(TileRect{0, 0, pixels, 1}), next_batch};
}

TEST(MergeCache, TakesOnlyAnEntryOfTheRightBatch) {
  MergeCache cache;
  cache.put(1, 0, tile_of(4, 3));
  EXPECT_EQ(cache.take(1, 0, 2), std::nullopt);  // stale: dropped
  EXPECT_EQ(cache.entries(), 0u);
  cache.put(1, 0, tile_of(4, 3));
  const std::optional<MergeCache::Tile> t = cache.take(1, 0, 3);
  ASSERT_TRUE(t);
  EXPECT_EQ(t->sum.pixels(), 4u);
  EXPECT_EQ(cache.entries(), 0u);  // taken out until put back
  EXPECT_EQ(cache.bytes(), 0u);
}

TEST(MergeCache, EvictsTheLeastRecentlyUsedBeyondItsBudget) {
  const size_t one = MergeCache::bytes_of(tile_of(100, 0).sum);
  MergeCache cache(2 * one);
  cache.put(1, 0, tile_of(100, 1));
  cache.put(1, 1, tile_of(100, 1));
  ASSERT_TRUE(cache.take(1, 0, 1));  // tile 0 used: now the most recent
  cache.put(1, 0, tile_of(100, 2));
  cache.put(2, 0, tile_of(100, 1));  // over budget: tile 1 of job 1 goes
  EXPECT_EQ(cache.entries(), 2u);
  EXPECT_LE(cache.bytes(), cache.budget_bytes());
  EXPECT_EQ(cache.take(1, 1, 1), std::nullopt);
  EXPECT_TRUE(cache.take(1, 0, 2));
  cache.put(3, 0, tile_of(1000, 1));  // larger than the whole budget: not kept at all
  EXPECT_LE(cache.bytes(), cache.budget_bytes());
  cache.forget_job(2);
  EXPECT_EQ(cache.take(2, 0, 1), std::nullopt);
}

/// Runs a 4-tile, 20-batch job with results arriving in a seeded shuffled order within each
/// round of leases, through a merger built by `make` (rebuilt after every `restart_every`
/// accepts: an empty cache, as after a server restart). Returns each tile's stored sum.
template <typename Make>
std::vector<std::string> run_job(Make make, int restart_every, size_t* max_unchecked_rows) {
  StoreFixture f;
  const int64_t job = f.make_job(8, 8, 4, 20, 1);  // 4 tiles x 20 batches of 1 spp
  const std::vector<TileRecord> rects = f.jobs.tiles(job);
  std::unique_ptr<TileMerger> merger = make(f);
  std::mt19937 rng(7);
  int accepted = 0;
  *max_unchecked_rows = 0;
  for (;;) {
    std::vector<Lease> round;
    for (int i = 0; i < 6; ++i) {
      if (const auto l = f.book.lease_next(f.make_worker())) round.push_back(*l);
    }
    if (round.empty()) break;
    std::shuffle(round.begin(), round.end(), rng);
    for (const Lease& l : round) {
      const Accumulation acc = StoreFixture::synthetic(rects[l.tile].rect, l.batch, 1);
      EXPECT_TRUE(merger->accept(result_for(l, acc), acc).accepted);
      if (++accepted % restart_every == 0) merger = make(f);
      // Merged rows outside the checkpoint (those waiting for a predecessor not counted).
      auto q = f.db.prepare(
          "SELECT COUNT(*) FROM results r JOIN tiles t ON t.job_id = r.job_id AND t.tile = r.tile"
          " WHERE r.batch < t.next_batch GROUP BY r.tile");
      while (q->step()) *max_unchecked_rows = std::max(*max_unchecked_rows, size_t(q->int64(0)));
    }
  }
  EXPECT_TRUE(f.jobs.get(job)->complete);
  merger->checkpoint_job(job);
  std::vector<std::string> sums;
  for (const TileRecord& t : f.jobs.tiles(job)) sums.push_back(t.accumulation);
  return sums;
}

// The reference: each tile's batches 0..19 added in order to zeros, encoded once as the merger
// encodes checkpoints (TileMerger::kCheckpointEffort).
std::vector<std::string> reference_sums() {
  std::vector<std::string> sums;
  for (int t = 0; t < 4; ++t) {
    const TileRect rect{(t % 2) * 4, (t / 2) * 4, (t % 2) * 4 + 4, (t / 2) * 4 + 4};
    Accumulation sum(rect);
    for (uint32_t b = 0; b < 20; ++b) sum.merge(StoreFixture::synthetic(rect, b, 1));
    sums.push_back(encode_accumulation(sum, TileMerger::kCheckpointEffort));
  }
  return sums;
}

TEST(MergeCheckpoints, SumsAreBitIdenticalWithOrWithoutTheCacheAndAcrossRestarts) {
  const std::vector<std::string> expected = reference_sums();
  size_t rows = 0;
  // The default: everything stays in memory, a checkpoint every kCheckpointEvery batches.
  EXPECT_EQ(run_job([](StoreFixture& f) { return std::make_unique<TileMerger>(f.db, f.clock); },
                    1 << 30, &rows),
            expected);
  EXPECT_LT(rows, size_t(TileMerger::kCheckpointEvery));
  // No memory at all: every merge rebuilds the sum from checkpoint + merged results.
  EXPECT_EQ(run_job([](StoreFixture& f) { return std::make_unique<TileMerger>(f.db, f.clock, 0, 5); },
                    1 << 30, &rows),
            expected);
  EXPECT_LE(rows, 4u);  // at most checkpoint_every - 1 rows per tile wait for a checkpoint
  EXPECT_GT(rows, 0u);
  // Restarts (a fresh merger, empty cache) every 7 accepted results.
  EXPECT_EQ(run_job([](StoreFixture& f) { return std::make_unique<TileMerger>(f.db, f.clock, 1 << 20, 3); },
                    7, &rows),
            expected);
}

TEST(MergeCheckpoints, MemoryStaysWithinTheBudget) {
  StoreFixture f;
  const int64_t job = f.make_job(64, 64, 8, 2, 1);  // 64 tiles of 8x8, 2 batches
  const size_t one_tile = MergeCache::bytes_of(Accumulation(TileRect{0, 0, 8, 8}));
  TileMerger merger(f.db, f.clock, 5 * one_tile);
  const std::vector<TileRecord> rects = f.jobs.tiles(job);
  while (const auto l = f.book.lease_next(f.make_worker())) {
    const Accumulation acc = StoreFixture::synthetic(rects[l->tile].rect, l->batch, 1);
    ASSERT_TRUE(merger.accept(result_for(*l, acc), acc).accepted);
    EXPECT_LE(merger.cache().bytes(), 5 * one_tile);
  }
  EXPECT_EQ(merger.cache().entries(), 5u);
  // Every tile reached 2 spp: finished tiles are checkpointed, nothing is left outside.
  auto q = f.db.prepare("SELECT COUNT(*) FROM results");
  ASSERT_TRUE(q->step());
  EXPECT_EQ(q->int64(0), 0);
  for (const TileRecord& t : f.jobs.tiles(job)) {
    for (uint32_t n : decode_accumulation(t.accumulation).count) ASSERT_EQ(n, 2u);
  }
}

// A row that does not continue the checkpoint (a damaged store) is refused, not merged.
TEST(MergeCheckpoints, AGapInTheMergedResultsIsAnError) {
  StoreFixture f;
  const int64_t job = f.make_job(4, 4, 4, 20, 1);
  TileMerger merger(f.db, f.clock, 0, 10);  // no cache: every merge reads the rows
  for (int i = 0; i < 3; ++i) {
    const Lease l = *f.book.lease_next(f.make_worker());
    const Accumulation acc = StoreFixture::synthetic({0, 0, 4, 4}, l.batch, 1);
    ASSERT_TRUE(merger.accept(result_for(l, acc), acc).accepted);
  }
  f.db.prepare("DELETE FROM results WHERE job_id = ? AND batch = 1")->bind(1, job).run();
  const Lease l = *f.book.lease_next(f.make_worker());
  const Accumulation acc = StoreFixture::synthetic({0, 0, 4, 4}, l.batch, 1);
  EXPECT_THROW(merger.accept(result_for(l, acc), acc), FarmError);
}

}  // namespace
}  // namespace tessera::server
