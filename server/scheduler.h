// Hands out work units: one SQL query orders the queue by job priority (higher first), then job
// age (older first), then batch, then tile, so a job's tiles progress together (a preview that
// sharpens evenly) and each tile's batches arrive roughly in merge order.
#pragma once

#include <cstdint>
#include <optional>

#include "job_store.h"
#include "lease_table.h"
#include "store/sqlite.h"

namespace tessera::server {

class Scheduler {
 public:
  Scheduler(Database& db, LeaseTable& leases, const Clock& clock)
      : db_(db), leases_(leases), clock_(clock) {}

  /// The worker's lease. Idempotent: a worker that already holds a lease gets the same lease
  /// (same id, expiry extended) — a retried call after a lost reply leases nothing new. Otherwise
  /// leases the first queued unit of a queued/running job the worker is not blocked from, and
  /// starts the job (queued -> running). nullopt when there is no work: a normal answer.
  std::optional<Lease> lease_next(int64_t worker_id);

 private:
  Database& db_;
  LeaseTable& leases_;
  const Clock& clock_;
};

}  // namespace tessera::server
