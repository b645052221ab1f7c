// The results table (migration 8): every accepted result of a tile that is not in the tile's
// checkpoint yet, as uploaded (encode_accumulation bytes), written once when it is accepted.
// Whether a row is merged or waiting follows from its tile's `next_batch` alone:
//
//   batch <  tiles.next_batch   merged into the tile's sum since its last checkpoint
//                               (the checkpoint holds [0, c), these rows [c, next_batch));
//   batch >= tiles.next_batch   accepted before an earlier batch of its tile: waiting.
//
// So merging a waiting result changes no row of this table (the tile's next_batch moves past
// it), and a checkpoint deletes the rows below next_batch. Before migration 8 a result that
// arrived early was written to pending_results, then copied to merged_results when merged:
// twice its bytes through the WAL.
//
// Every statement on `results` is here, each operation one event of a result's life: accepted
// (append), merged (nothing to write), checkpointed (drop_merged), wasted when its tile or job
// closed before its predecessors merged (drop_waiting_*). The caller holds the transaction.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "store/sqlite.h"

namespace tessera::server {

class ResultsTable {
 public:
  explicit ResultsTable(Database& db) : db_(db) {}

  /// An accepted result, its bytes as uploaded. Throws (the primary key) when the batch of the
  /// tile already has a row: the unit's compare-and-set lets one result per unit through.
  void append(int64_t job_id, uint32_t tile, uint32_t batch, const std::string& encoded);

  /// The bytes of the tile's result for `batch`, when one was accepted and is not checkpointed.
  std::optional<std::string> find(int64_t job_id, uint32_t tile, uint32_t batch);

  /// The first batch of the tile with a merged row (below `next_batch`); `next_batch` when
  /// the checkpoint holds every merged batch.
  uint32_t first_merged(int64_t job_id, uint32_t tile, uint32_t next_batch);

  /// Calls `each(batch, bytes)` for the tile's merged rows (batches below `next_batch`) in
  /// batch order.
  void for_each_merged(int64_t job_id, uint32_t tile, uint32_t next_batch,
                       const std::function<void(uint32_t, const std::string&)>& each);

  /// Checkpointed: the tile's checkpoint now holds every batch below `next_batch`; their rows
  /// go. Returns the rows deleted.
  int64_t drop_merged(int64_t job_id, uint32_t tile, uint32_t next_batch);

  /// Wasted: the tile closed (its stopping rule finished it) with `next_batch` merged; the
  /// results waiting for later batches will never merge. Returns the rows deleted.
  int64_t drop_waiting_of_tile(int64_t job_id, uint32_t tile, uint32_t next_batch);

  /// Wasted: the job ended (settled, cancelled or failed); every result of it still waiting for
  /// an earlier batch of its tile goes. Merged rows stay (the tile's sum needs them until its
  /// checkpoint). Returns the rows deleted.
  int64_t drop_waiting_of_job(int64_t job_id);

  /// The job's tiles with merged rows outside their checkpoint (tile numbers, ascending).
  std::vector<uint32_t> tiles_with_merged(int64_t job_id);

  /// The job's tiles with any row (merged or waiting), ascending: what a merger starting on
  /// the job may find waiting in the store (TileMerger::may_wait_in_store).
  std::vector<uint32_t> tiles_with_rows(int64_t job_id);

  /// Rows of the job (merged and waiting), for tests and checks.
  int64_t count(int64_t job_id);

 private:
  Database& db_;
};

}  // namespace tessera::server
