#include "lease_table.h"

#include <sys/random.h>

#include <cerrno>
#include <limits>
#include <system_error>
#include <vector>

#include "store/failures_table.h"
#include "store/jobs_table.h"
#include "store/tile_queue.h"
#include "store/workers_table.h"

namespace tessera::server {
std::string random_lease_id() {
  // One getrandom(2) call: no file to open and close per id, as std::random_device did here (4 % of
  // the server's CPU in a profile of 16 units per call: BENCHMARKS.md, "What a result and a job
  // cost the server, counted").
  unsigned char bytes[16];
  size_t got = 0;
  while (got < sizeof bytes) {
    const ssize_t n = getrandom(bytes + got, sizeof bytes - got, 0);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw std::system_error(errno, std::generic_category(), "getrandom (a lease id)");
    }
    got += size_t(n);
  }
  static constexpr char kHex[] = "0123456789abcdef";
  std::string id;
  id.reserve(2 * sizeof bytes);
  for (const unsigned char byte : bytes) {
    id.push_back(kHex[byte >> 4]);
    id.push_back(kHex[byte & 15]);
  }
  return id;
}

LeaseTable::LeaseTable(Database& db, JobStore& jobs, const Clock& clock, int64_t lease_ms,
                       IdSource new_id)
    : db_(db), units_(db), jobs_(jobs), clock_(clock), lease_ms_(lease_ms), new_id_(std::move(new_id)) {}

std::optional<int64_t> LeaseTable::record_grant(const Lease& lease, bool unborn) {
  if (unborn) {
    if (!TileQueue(db_).take(lease.job_id, lease.tile, lease.batch)) return std::nullopt;
    return units_.insert_leased(lease.job_id, lease.tile, lease.batch, lease.worker_id,
                                lease.lease_id, lease.expires_unix_ms);
  }
  if (units_.lease_requeued(lease.unit_id, lease.worker_id, lease.lease_id,
                            lease.expires_unix_ms) != 1) {
    return std::nullopt;
  }
  return lease.unit_id;
}

std::vector<Lease> LeaseTable::expire(const std::vector<Lease>& leases) {
  std::vector<Lease> done;
  Transaction tx(db_);
  for (const Lease& e : leases) {
    if (units_.requeue(e.unit_id, e.lease_id, UnitEvent::expire, false) != 1) continue;
    done.push_back(e);
    JobsTable(db_).count_expired(e.job_id);
    WorkersTable(db_).count_lost(e.worker_id);
  }
  tx.commit();
  return done;
}

ReleaseOutcome LeaseTable::release(int64_t worker_id, const std::string& lease_id,
                                   ReleaseReason reason, const std::string& message) {
  ReleaseOutcome outcome;
  Transaction tx(db_);
  const std::optional<Lease> held = units_.lease(worker_id, lease_id);
  if (!held) return outcome;
  const int64_t unit_id = held->unit_id, job_id = held->job_id;
  const bool failed = reason == ReleaseReason::failed;
  outcome.released = units_.requeue(unit_id, lease_id, UnitEvent::release, failed) == 1;
  JobsTable(db_).count_released(job_id);
  if (failed) outcome.job_failed = record_failure(unit_id, job_id, worker_id, message);
  tx.commit();
  return outcome;
}

bool LeaseTable::record_failure(int64_t unit_id, int64_t job_id, int64_t worker_id,
                                const std::string& message) {
  const int64_t now = clock_.now_unix_ms();
  // A failure after the forgiveness window starts the worker's count on this job again.
  FailuresTable failures(db_);
  failures.record(job_id, unit_id, worker_id, message, now, forgiven_before_unix_ms());
  int64_t workers = 0, attempts = 0;
  std::string reasons;
  for (const UnitFailure& f : failures.of_unit(unit_id)) {
    ++workers;
    attempts += f.failures;
    reasons += std::string(reasons.empty() ? "" : "; ") + "worker " +
               std::to_string(f.worker_id) + " (" + f.worker_name + "): " + f.last_error;
  }
  const int64_t max_attempts = int64_t(policy_.workers_to_fail_unit) * policy_.failures_to_block;
  if (workers < policy_.workers_to_fail_unit && attempts < max_attempts) return false;
  const auto [tile, batch] = units_.tile_batch(unit_id).value_or(std::pair(0u, 0u));
  return jobs_.fail_in_transaction(job_id,
                                   "unit (tile " + std::to_string(tile) + ", batch " +
                                       std::to_string(batch) + ") failed " +
                                       std::to_string(attempts) + " time(s) on " +
                                       std::to_string(workers) + " worker(s): " + reasons,
                                   now);
}

int LeaseTable::requeue_expiring_before(int64_t bound) {
  int count = 0;
  for (const Lease& e : units_.leases_expiring_before(bound)) {
    if (units_.requeue(e.unit_id, e.lease_id, UnitEvent::expire, false) != 1) continue;
    ++count;
    JobsTable(db_).count_expired(e.job_id);
    WorkersTable(db_).count_lost(e.worker_id);
  }
  return count;
}

std::vector<int64_t> LeaseTable::enforce_time_budgets() {
  const int64_t now = clock_.now_unix_ms();
  Transaction tx(db_);
  JobsTable jobs(db_);
  const std::vector<int64_t> over = jobs.running_over_budget(now);
  std::vector<int64_t> complete;
  for (int64_t job_id : over) {
    // Batch 0 is never skipped: every tile gets it, even after the budget.
    const int64_t skipped_rows = units_.skip_queued_after_first_batch(job_id);
    // ...and so are those without a row yet.
    const int64_t n = skipped_rows + TileQueue(db_).skip_after_first_batch(job_id);
    jobs.count_budget_reached(job_id, n, now);
    if (!units_left(db_, job_id)) complete.push_back(job_id);
  }
  tx.commit();
  return complete;
}

int LeaseTable::revoke_all() {
  Transaction tx(db_);
  const int count = requeue_expiring_before(std::numeric_limits<int64_t>::max());
  tx.commit();
  return count;
}

}  // namespace tessera::server
