// The tile_queue table (migration 6): the units of each tile that have no row yet. A job's units
// come into being when leased, so a submit writes O(tiles) rows whatever its spp: for each tile,
// batches [next_lease, lease_end) are queued without a row in `units`, and the lease event
// inserts the row of batch next_lease (state 'leased') and moves next_lease on. Units that came
// back from a lease (expired, released) keep their row in `units`, state 'queued'.
//
// Every operation here is one of the unit state machine's events (store/job_state.h) applied
// to the units without a row, as compare-and-set on next_lease or lease_end.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "store/sqlite.h"

namespace tessera::server {

/// A tile's row of unborn units: batches [next_lease, lease_end) have no row yet.
struct TileQueueRow {
  uint32_t tile = 0;
  uint32_t next_lease = 0;
  uint32_t lease_end = 0;
};

class TileQueue {
 public:
  explicit TileQueue(Database& db) : db_(db) {}

  /// At submit: every tile [0, tiles) of `job_id` has batches [0, batch_count) to lease.
  /// The tiles' rows must exist (foreign key). Call inside a transaction.
  void create(int64_t job_id, uint32_t tiles, uint32_t batch_count);

  /// UnitEvent::lease on an unborn unit, the compare-and-set half: next_lease batch -> batch
  /// + 1. False when another lease took it first (or the tile was closed). Call inside the
  /// transaction that inserts the unit's row.
  bool take(int64_t job_id, uint32_t tile, uint32_t batch);

  /// UnitEvent::skip of every unborn unit of the tile (its stopping rule closed it). Returns
  /// how many units that skipped.
  int64_t close_tile(int64_t job_id, uint32_t tile);

  /// UnitEvent::cancel of every unborn unit of the job (it was cancelled or failed). Returns
  /// how many.
  int64_t close_job(int64_t job_id);

  /// The time rule past the budget: UnitEvent::skip of every unborn unit of a batch > 0 (batch
  /// 0 of every tile is still leased). Returns how many units that skipped.
  int64_t skip_after_first_batch(int64_t job_id);

  /// Every row of the job, by tile (the lease book loads them: server/lease_book.h).
  std::vector<TileQueueRow> rows(int64_t job_id);

  /// True when some unit of the job has no row yet (and may still be leased).
  bool any_open(int64_t job_id);

 private:
  /// Lowers lease_end to `new_end` (an SQL expression of the row, at least next_lease) in the
  /// job's open rows (one tile's, when given) where it is above it: those unborn units will
  /// never be leased. Returns how many units that closed.
  int64_t lower_lease_end(int64_t job_id, std::optional<uint32_t> tile, const std::string& new_end);

  Database& db_;
};

}  // namespace tessera::server
