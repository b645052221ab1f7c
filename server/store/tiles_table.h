// The tiles table: one row per tile of a job, its rectangle, its merged prefix (`next_batch`)
// and its stopping-rule verdict; and its checkpoint (the encoded sum of batches the results
// table no longer holds), in `tile_checkpoints` (migration 10: a blob in the tiles row made
// every read of its later columns and every merge's UPDATE walk the blob's overflow pages).
// Every statement on `tiles` and `tile_checkpoints` is here. The merge moves `next_batch` by
// compare-and-set (`advance`): a tile that changed under a merge is an internal error.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "accum/tile_rect.h"
#include "store/job_record.h"
#include "store/sqlite.h"

namespace tessera::server {

/// A tile's rectangle and merged prefix (the merger's view).
struct TilePosition {
  TileRect rect;
  uint32_t next_batch = 0;
};

/// What a merge leaves on a tile (TilesTable::advance).
struct TileProgress {
  uint32_t next_batch = 0;    ///< batches [0, next_batch) merged
  /// Estimated relative error of the merged tile; nullopt keeps the stored one (the merger
  /// computes it only where the rule reads it or at checkpoints: server/tile_merger.cpp).
  std::optional<double> error;
  StopReason finished = StopReason::none;  ///< the verdict that closed it; none = open
  uint32_t spp = 0;           ///< samples per pixel merged
};

class TilesTable {
 public:
  explicit TilesTable(Database& db) : db_(db) {}

  /// At submit: the job's tiles, numbered in order. Call inside the submit's transaction.
  void insert(int64_t job_id, const std::vector<TileRect>& tiles);

  /// Every tile of the job with its checkpoint bytes, in tile order.
  std::vector<TileRecord> of_job(int64_t job_id);
  std::optional<TileRect> rect(int64_t job_id, uint32_t tile);
  std::optional<TilePosition> position(int64_t job_id, uint32_t tile);
  /// Every tile's rectangle and merged prefix, in tile order (no checkpoint bytes): what the
  /// lease book (server/lease_book.h) loads of a job.
  std::vector<TilePosition> positions(int64_t job_id);
  /// The checkpoint's encode_accumulation bytes; nullopt when nothing was checkpointed.
  std::optional<std::string> checkpoint(int64_t job_id, uint32_t tile);
  /// How many of the job's tiles were closed by `reason`.
  int64_t count_finished_by(int64_t job_id, StopReason reason);

  /// A merge: the tile's prefix moves from `from_next_batch` to `p.next_batch` with its
  /// verdict. False when the tile's next_batch was no longer `from_next_batch`.
  bool advance(int64_t job_id, uint32_t tile, uint32_t from_next_batch, const TileProgress& p);
  /// A checkpoint: `encoded` is now the tile's stored sum.
  void write_checkpoint(int64_t job_id, uint32_t tile, const std::string& encoded);

 private:
  Database& db_;
};

}  // namespace tessera::server
