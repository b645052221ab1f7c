// Decoded tiles kept in memory between merges, so that accepting a result does not decode the
// stored tile, add the batch and encode it again each time (BENCHMARKS.md, "Merge throughput"). A
// pure cache of what the store holds: a tile's merged sum is always its checkpoint
// (tile_checkpoints.accumulation, batches [0, c)) plus the merged rows of the results table
// (batches [c, next_batch)), replayed in batch order; an entry is that sum decoded, valid while its
// next_batch matches the store's. So an entry may be dropped at any time (eviction, an exception in
// a transaction, a restart) and is rebuilt bit for bit from the store (the codec is lossless).
//
// Memory: at most `budget_bytes` of decoded tiles (36 bytes per pixel: four double sums and a
// count) plus the tiles being merged at the moment (one per upload in progress: one, since the
// coordinator serialises merges). Least recently used entries go first.
#pragma once

#include <cstdint>
#include <optional>
#include <utility>

#include "accum/accumulation.h"
#include "byte_bounded_lru.h"

namespace tessera::server {

class MergeCache {
 public:
  /// A tile's merged sum of batches [0, next_batch).
  struct Tile {
    Accumulation sum;
    uint32_t next_batch = 0;
    /// Batches [0, checkpointed) are in the stored checkpoint, [checkpointed, next_batch) in
    /// the results table (store/results_table.h).
    uint32_t checkpointed = 0;
  };

  /// The coordinator's default bound (CoordinatorConfig::merge_cache_bytes, --merge-cache-mb).
  static constexpr size_t kDefaultBudgetBytes = size_t(1) << 30;

  explicit MergeCache(size_t budget_bytes = kDefaultBudgetBytes) : lru_(budget_bytes) {}

  /// Removes the entry of (job, tile) and returns it when it holds batches [0, next_batch);
  /// nullopt otherwise (a stale entry is dropped). The caller puts it back with put() once its
  /// transaction has committed.
  std::optional<Tile> take(int64_t job_id, uint32_t tile, uint32_t next_batch);

  /// Stores `t` as the most recently used entry, evicting the least recently used ones while
  /// the bytes exceed the budget (`t` itself too when it alone exceeds it).
  void put(int64_t job_id, uint32_t tile, Tile t);

  /// Drops every entry of the job (deleted).
  void forget_job(int64_t job_id);

  size_t bytes() const { return lru_.bytes(); }
  size_t entries() const { return lru_.entries(); }
  size_t budget_bytes() const { return lru_.budget_bytes(); }

  /// Bytes an entry of this sum counts against the budget.
  static size_t bytes_of(const Accumulation& sum);

 private:
  using Key = std::pair<int64_t, uint32_t>;  ///< (job, tile)
  ByteBoundedLru<Key, Tile> lru_;
};

}  // namespace tessera::server
