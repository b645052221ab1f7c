// Decoded results waiting for an earlier batch of their tile, kept in memory so that merging
// one later neither reads its row back from the store nor decodes it a second time (it was
// decoded once already, to be checked when it was uploaded). A pure cache of the waiting rows of
// the results table (store/results_table.h): an entry may be missing at any time (evicted, a
// transaction rolled back, a restart), and the merger then reads the row as before; an entry
// is only ever taken for the one result its (job, tile, batch) names, accepted once.
//
// Memory: at most `budget_bytes` of decoded results (MergeCache::bytes_of each); the oldest
// entries go first.
#pragma once

#include <cstdint>
#include <optional>
#include <tuple>
#include <utility>
#include <vector>

#include "accum/accumulation.h"
#include "byte_bounded_lru.h"

namespace tessera::server {

class WaitingResults {
 public:
  explicit WaitingResults(size_t budget_bytes) : lru_(budget_bytes) {}

  /// Keeps the decoded result of (job, tile, batch), evicting the oldest entries while the
  /// bytes exceed the budget (this one too when it alone exceeds it). Returns the (job, tile)
  /// of each entry evicted: their rows are now only in the store.
  std::vector<std::pair<int64_t, uint32_t>> put(int64_t job_id, uint32_t tile, uint32_t batch,
                                                Accumulation result);
  /// Removes and returns the entry of (job, tile, batch); nullopt when there is none.
  std::optional<Accumulation> take(int64_t job_id, uint32_t tile, uint32_t batch);
  /// Drops every entry of the job (deleted).
  void forget_job(int64_t job_id);

  size_t bytes() const { return lru_.bytes(); }
  size_t entries() const { return lru_.entries(); }

 private:
  using Key = std::tuple<int64_t, uint32_t, uint32_t>;  ///< (job, tile, batch)
  ByteBoundedLru<Key, Accumulation> lru_;
};

}  // namespace tessera::server
