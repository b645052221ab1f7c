// The units table: the rows of work units that were leased at least once (the others wait in
// store/tile_queue.h). Every statement on `units` is here, each operation one event of the unit
// state machine (store/job_state.h) applied as compare-and-set: `UPDATE units SET state = <to>
// ... WHERE ... AND state = <from>` changes nothing when another call got there first, and the
// caller learns it from the returned count.
//
// States appear in the SQL as literals ('leased'), never as bound parameters: a parameter
// compared with `state` makes SQLite compile the statement again at every call (the partial
// indexes on leased units name the literal) and keeps it off those indexes, so a worker's
// lease would be found by a scan of every unit row (BENCHMARKS.md, "What a result and a job
// cost the server, counted").
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "accum/tile_rect.h"
#include "job/job_plan.h"
#include "job/stopping_rule.h"
#include "store/job_state.h"
#include "store/sqlite.h"

namespace tessera::server {

/// A unit's row while it is leased: the lease a worker holds (server/lease_table.h).
struct Lease {
  std::string lease_id;
  int64_t unit_id = 0;
  int64_t job_id = 0;
  uint32_t tile = 0;
  uint32_t batch = 0;
  int64_t worker_id = 0;
  int64_t expires_unix_ms = 0;
};

/// A unit back in the queue (it has a row: an earlier lease expired or was handed back).
/// A unit with what judging its result needs of its tile and job (UnitsTable::for_result).
struct UnitForResult {
  int64_t unit_id = 0;
  TileRect rect;              ///< its tile's pixels
  uint32_t next_batch = 0;    ///< its tile's merged prefix
  JobPlan plan;               ///< its job's size, tiles and batch schedule
  StopRule rule = StopRule::spp;
  double noise_target = 0;
  bool cancelled = false;     ///< cancelled (its job ended, or the stopping rule skipped it)
};

/// A unit row that is queued or leased (UnitsTable::live): `lease` is set when leased.
struct LiveUnit {
  int64_t unit_id = 0;
  uint32_t tile = 0;
  uint32_t batch = 0;
  std::optional<Lease> lease;
};

class UnitsTable {
 public:
  explicit UnitsTable(Database& db) : db_(db) {}

  // ---- Reads ---------------------------------------------------------------------------------
  /// The unit `lease_id` names when it is current and held by `worker_id`; nullopt otherwise.
  std::optional<Lease> lease(int64_t worker_id, const std::string& lease_id);
  /// Every lease expiring before `bound` (by the partial index units_expiry).
  std::vector<Lease> leases_expiring_before(int64_t bound);
  /// The job's rows that are queued or leased, in (batch, tile) order (by the units_queue
  /// index): what the lease book loads of a job (server/lease_book.h).
  std::vector<LiveUnit> live(int64_t job_id);
  /// True when a unit of the job with a row is queued or leased.
  bool any_queued_or_leased(int64_t job_id);
  /// The unit (job, tile, batch) with its tile and job, in one join; nullopt when it has no row.
  std::optional<UnitForResult> for_result(int64_t job_id, uint32_t tile, uint32_t batch);
  /// Units leased now, farm-wide (by the partial index units_expiry).
  int64_t count_leased();
  /// The (tile, batch) of a unit; nullopt for an unknown id.
  std::optional<std::pair<uint32_t, uint32_t>> tile_batch(int64_t unit_id);

  // ---- Events (compare-and-set; each returns the rows it changed) ----------------------------
  /// UnitEvent::lease of a requeued unit: queued -> leased to `worker_id` with `lease_id`.
  int lease_requeued(int64_t unit_id, int64_t worker_id, const std::string& lease_id,
                     int64_t expires_unix_ms);
  /// UnitEvent::lease of a unit without a row: the row is born leased (the tile_queue half is
  /// TileQueue::take, in the same transaction). Returns the new unit's id.
  int64_t insert_leased(int64_t job_id, uint32_t tile, uint32_t batch, int64_t worker_id,
                     const std::string& lease_id, int64_t expires_unix_ms);
  /// A lease granted in memory that the store refused (server/lease_book.h: its tile closed or
  /// its job ended first): the unit's row, born cancelled, so that the lease's result is
  /// dropped as a cancelled unit's. Nothing when the row exists.
  void insert_cancelled(int64_t job_id, uint32_t tile, uint32_t batch);
  /// UnitEvent::accept: leased -> done on the current lease of `worker_id` (the row keeps the
  /// worker that delivered it).
  int accept(int64_t unit_id, int64_t worker_id, const std::string& lease_id);
  /// UnitEvent::expire or UnitEvent::release: leased -> queued, the lease cleared; a release
  /// for a failure also counts it on the unit.
  int requeue(int64_t unit_id, const std::string& lease_id, UnitEvent event, bool failure);
  /// UnitEvent::skip of the tile's queued and leased units (its stopping rule closed it).
  int64_t skip_tile(int64_t job_id, uint32_t tile);
  /// UnitEvent::cancel of the job's queued and leased units (it was cancelled or failed).
  int64_t cancel_job(int64_t job_id);
  /// The time rule past the budget: UnitEvent::skip of the job's queued units of batches > 0.
  int64_t skip_queued_after_first_batch(int64_t job_id);

 private:
  /// The one statement that ends leases: `event` on every unit in state `from` matching
  /// `where` (SQL over the row; `bind` binds its parameters): the state becomes
  /// next_state(from, event), lease id, worker and expiry are cleared, and `extra_set` (e.g.
  /// ", failures = failures + 1") is applied. Returns the rows changed.
  int64_t end_leases(UnitEvent event, UnitState from, const std::string& where,
                     const std::function<void(Statement&)>& bind,
                     const std::string& extra_set = "");

  Database& db_;
};

}  // namespace tessera::server
