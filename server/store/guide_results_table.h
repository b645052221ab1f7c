// The guide_results table (migration 13): the denoiser's guides of each accepted unit of a
// denoise job that rendered them (its samples below kGuideSamples), as uploaded
// (encode_guide_tile bytes), written in the transaction that accepts the unit's result. They are
// merged per tile, in batch order over the tile's merged batches, only when the job's image is
// written or previewed (server/job_guides.h): no merge state to keep, and nothing lost at a
// restart. A job's rows go with its tiles (ON DELETE CASCADE).
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "store/sqlite.h"

namespace tessera::server {

class GuideResultsTable {
 public:
  explicit GuideResultsTable(Database& db) : db_(db) {}

  /// The accepted unit's guides, stored only when its job was submitted with denoise; returns
  /// false (nothing stored) otherwise. The unit's compare-and-set lets one result per unit
  /// through; a row already there (the same unit accepted before a restart) is replaced.
  bool put(int64_t job_id, uint32_t tile, uint32_t batch, const std::string& encoded);

  /// Calls `each(batch, bytes)` for the tile's rows below `next_batch`, in batch order.
  void for_each_below(int64_t job_id, uint32_t tile, uint32_t next_batch,
                      const std::function<void(uint32_t, const std::string&)>& each);

 private:
  Database& db_;
};

}  // namespace tessera::server
