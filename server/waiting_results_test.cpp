// Waiting results kept decoded (server/waiting_results.h): bounded, and merging from memory
// gives the same bits as reading the rows back.
#include "waiting_results.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "accum/accumulation_codec.h"
#include "store_fixture.h"

namespace tessera::server {
namespace {

using testing::StoreFixture;
using testing::result_for;

Accumulation result_of(int pixels, uint32_t batch) {
  return StoreFixture::synthetic(TileRect{0, 0, pixels, 1}, batch, 1);
}

TEST(WaitingResults, TakesEachEntryOnceAndStaysWithinItsBudget) {
  const size_t one = MergeCache::bytes_of(result_of(100, 0));
  WaitingResults w(2 * one);
  w.put(1, 0, 3, result_of(100, 3));
  w.put(1, 0, 4, result_of(100, 4));
  EXPECT_EQ(w.take(1, 0, 3), result_of(100, 3));
  EXPECT_EQ(w.take(1, 0, 3), std::nullopt);  // taken
  w.put(1, 1, 5, result_of(100, 5));
  w.put(2, 0, 1, result_of(100, 1));  // over budget: the oldest (1, 0, 4) goes
  EXPECT_EQ(w.entries(), 2u);
  EXPECT_LE(w.bytes(), 2 * one);
  EXPECT_EQ(w.take(1, 0, 4), std::nullopt);
  w.forget_job(1);
  EXPECT_EQ(w.take(1, 1, 5), std::nullopt);
  EXPECT_TRUE(w.take(2, 0, 1).has_value());
  w.put(3, 0, 0, result_of(1000, 0));  // larger than the whole budget: not kept
  EXPECT_EQ(w.entries(), 0u);
  EXPECT_EQ(w.bytes(), 0u);
}

/// Runs a 4-tile, 16-batch job with results in a seeded shuffled order through a merger with
/// `cache_bytes`; returns the tiles' stored sums and the merger's (waiting merged, from memory).
std::pair<std::vector<std::string>, std::pair<uint64_t, uint64_t>> run(size_t cache_bytes) {
  StoreFixture f;
  const int64_t job = f.make_job(8, 8, 4, 16, 1);
  const std::vector<TileRecord> rects = f.jobs.tiles(job);
  TileMerger merger(f.db, f.clock, cache_bytes);
  std::mt19937 rng(5);
  for (;;) {
    std::vector<Lease> round;
    for (int i = 0; i < 10; ++i) {
      if (const auto l = f.book.lease_next(f.make_worker())) round.push_back(*l);
    }
    if (round.empty()) break;
    std::shuffle(round.begin(), round.end(), rng);
    for (const Lease& l : round) {
      const Accumulation acc = StoreFixture::synthetic(rects[l.tile].rect, l.batch, 1);
      EXPECT_TRUE(merger.accept(result_for(l, acc), acc).accepted);
    }
  }
  merger.checkpoint_job(job);
  std::vector<std::string> sums;
  for (const TileRecord& t : f.jobs.tiles(job)) sums.push_back(t.accumulation);
  return {sums, merger.waiting_merged()};
}

TEST(WaitingResults, MergedFromMemoryOrFromTheStoreTheBitsAreTheSame) {
  const auto [in_memory, hits] = run(MergeCache::kDefaultBudgetBytes);
  const auto [from_store, misses] = run(0);  // nothing kept: every waiting row read back
  EXPECT_EQ(in_memory, from_store);
  EXPECT_GT(hits.first, 10u);           // the shuffle made results wait
  EXPECT_EQ(hits.second, hits.first);   // ...and each came from memory
  EXPECT_EQ(misses.first, hits.first);  // the same merges
  EXPECT_EQ(misses.second, 0u);
}

}  // namespace
}  // namespace tessera::server
