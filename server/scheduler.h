// Hands out work units. Jobs are walked by priority (higher first), then age (older first); in
// the first job with a unit to give, two indexed queries (units back in the queue, and units
// not created yet: store/tile_queue.h) take its first queued unit by (batch, tile), so a job's tiles progress together (a preview that sharpens evenly) and each tile's
// batches arrive roughly in merge order: batch b+1 of a job is leased once no batch <= b of it is
// left unleased, without waiting for results (no barrier). The stopping rules act here too: a
// `time` job past its budget gets only what is left of batch 0 (every tile gets its first batch,
// nothing else starts), and a `noise` tile is leased at most kNoiseLookahead batches past its
// merged prefix (speculation the rule may waste, never a change of bits: see tile_merger.h).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "job_store.h"
#include "lease_table.h"
#include "store/sqlite.h"

namespace tessera::server {

class Scheduler {
 public:
  /// A noise tile with batches [0, next_batch) merged is leased batches < next_batch + this.
  static constexpr uint32_t kNoiseLookahead = 2;

  Scheduler(Database& db, LeaseTable& leases, const Clock& clock)
      : db_(db), leases_(leases), clock_(clock) {}

  /// The worker's lease. Idempotent: a worker that already holds a lease gets the same lease
  /// (same id, expiry extended) — a retried call after a lost reply leases nothing new. Otherwise
  /// leases the first queued unit of a queued/running job the worker is not blocked from (for a
  /// `time` job past its budget, started_unix_ms + budget <= now, a unit of batch 0 only), and
  /// starts the job (queued -> running). nullopt when there is no work: a normal answer.
  std::optional<Lease> lease_next(int64_t worker_id);

  /// Several leases in one transaction: every lease the worker holds (expiry extended: a
  /// retried call after a lost reply leases nothing twice) and new ones, picked as lease_next
  /// picks, until it holds `max_units`. Empty when it holds none and there is no work.
  std::vector<Lease> lease_up_to(int64_t worker_id, uint32_t max_units);

  /// The time rule's bookkeeping, called periodically (and before answering a lease): every
  /// running `time` job past its budget is marked (budget_reached_unix_ms) and its queued units
  /// of batches > 0 skipped (UnitEvent::skip; units back from an expired lease are skipped on
  /// the next call; batch 0 is leased again, whatever the time). Leased units are awaited: their results merge if their batch prefix is complete. Returns
  /// the ids of such jobs with no unit queued or leased left: ready to settle and finish.
  std::vector<int64_t> enforce_time_budgets();

 private:
  /// A leasable unit: with its row (unit_id) or without one yet (store/tile_queue.h).
  struct Pick {
    std::optional<int64_t> unit_id;
    uint32_t tile = 0, batch = 0;
  };
  /// The first leasable unit of `job_id` in (batch, tile) order, or nullopt.
  std::optional<Pick> first_unit(int64_t job_id, bool noise, bool over_budget);

  Database& db_;
  UnitsTable units_{db_};
  LeaseTable& leases_;
  const Clock& clock_;
};

}  // namespace tessera::server
