// The failure tables: `job_worker_failures` (a worker's recent failures on a job, which keep it
// from leasing that job) and `unit_failures` (each worker's failures on one unit, which fail the
// job when enough workers failed it). Both change only when a worker releases a unit as failed
// (LeaseTable::release); every statement on them is here.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "store/sqlite.h"

namespace tessera::server {

/// One worker's failures on one unit.
struct UnitFailure {
  int64_t worker_id = 0;
  std::string worker_name;
  int64_t failures = 0;
  std::string last_error;
};

/// A worker's count of recent failures on a job (job_worker_failures).
struct JobWorkerFailures {
  int64_t worker_id = 0;
  int64_t failures = 0;
  int64_t last_failure_unix_ms = 0;
};

class FailuresTable {
 public:
  explicit FailuresTable(Database& db) : db_(db) {}

  /// A failed release of `unit_id` of `job_id` by `worker_id` at `now_unix_ms`: counted on
  /// the unit, and on the job for the worker, whose count starts again at 1 when its last
  /// failure there was at or before `forgiven_before_unix_ms`.
  void record(int64_t job_id, int64_t unit_id, int64_t worker_id, const std::string& message,
              int64_t now_unix_ms, int64_t forgiven_before_unix_ms);
  /// The unit's failures, one entry per worker, by worker id.
  std::vector<UnitFailure> of_unit(int64_t unit_id);
  /// Every worker's failures on the job (the lease book's blocks: server/lease_book.h).
  std::vector<JobWorkerFailures> of_job(int64_t job_id);

 private:
  Database& db_;
};

}  // namespace tessera::server
