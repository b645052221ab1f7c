// Leases on work units in the store: a grant of the lease book written (server/lease_book.h),
// hand-backs, expiry and the time rule's skips. Which unit is leased is Scheduler's
// (server/scheduler.h); heartbeats are the book's alone.
// A lease is current while its unit is 'leased' with that lease_id; every change is a
// compare-and-set on (unit, lease_id, state), so a superseded lease can never change anything.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "clock.h"
#include "job_store.h"
#include "store/sqlite.h"
#include "store/units_table.h"

namespace tessera::server {

/// Why a unit is handed back.
enum class ReleaseReason { shutdown, failed };

struct ReleaseOutcome {
  bool released = false;   ///< false: the lease was not current, nothing changed
  bool job_failed =
      false;  ///< the unit failed on enough workers (WorkerHealthPolicy): its job failed
};

/// When failures block a worker from a job, and when they fail the job (docs/reliability.md,
/// "Worker health and shutdown"). Server flags set each.
struct WorkerHealthPolicy {
  /// A worker that fails this many units of one job (ReleaseUnit REASON_FAILED) gets no more of
  /// its units (--block-after-failures)...
  int failures_to_block = 2;
  /// ...until this long after its last failure there (--block-forgive-seconds); a failure after
  /// that starts its count again.
  int64_t forgive_ms = 600'000;
  /// A unit that failed on this many different workers fails its job, with every worker's
  /// reason (--unit-fail-workers). So that a farm with fewer workers still ends, a unit that
  /// failed workers_to_fail_unit * failures_to_block times in all fails its job too.
  int workers_to_fail_unit = 3;
};

/// 128 random bits as 32 lowercase hex characters (getrandom(2): the kernel's random source,
/// never a seeded generator). Throws std::system_error when the kernel refuses.
std::string random_lease_id();

class LeaseTable {
 public:
  using IdSource = std::function<std::string()>;

  LeaseTable(Database& db, JobStore& jobs, const Clock& clock, int64_t lease_ms,
             IdSource new_id = random_lease_id);

  int64_t lease_ms() const { return lease_ms_; }
  const WorkerHealthPolicy& health_policy() const { return policy_; }
  void set_health_policy(const WorkerHealthPolicy& policy) { policy_ = policy; }
  /// Failures before this time no longer block a worker (now - forgive_ms).
  int64_t forgiven_before_unix_ms() const { return clock_.now_unix_ms() - policy_.forgive_ms; }

  /// Writes a lease granted in memory (server/lease_book.h) to the store: for an unborn unit
  /// (`unborn`) TileQueue::take and the row born leased, else the requeued row `lease.unit_id`
  /// queued -> leased; with the lease's own id and expiry. Call inside a transaction. Returns
  /// the unit's id, or nullopt when the store no longer had the unit leasable (the lease is
  /// then void).
  std::optional<int64_t> record_grant(const Lease& lease, bool unborn);

  /// Each of `leases` (current in the store: unit, lease id) -> queued, counted as expired per
  /// job and lost per worker, in one transaction. Returns the leases it requeued (a lease no
  /// longer current is left out).
  std::vector<Lease> expire(const std::vector<Lease>& leases);

  /// leased -> queued. With ReleaseReason::failed the failure counts against the worker on that
  /// job (blocking it at policy.failures_to_block) and against the unit (failing the job, with
  /// every worker's reason, once policy.workers_to_fail_unit different workers failed it).
  ReleaseOutcome release(int64_t worker_id, const std::string& lease_id, ReleaseReason reason,
                         const std::string& message);

  /// The time rule's bookkeeping, called periodically (Leasing::expire_leases): every
  /// running `time` job past its budget is marked (budget_reached_unix_ms) and its queued units
  /// of batches > 0 skipped (UnitEvent::skip; units back from an expired lease are skipped on
  /// the next call; batch 0 is leased again, whatever the time: Scheduler). Leased units are
  /// awaited: their results merge if their batch prefix is complete. Returns the ids of such
  /// jobs with no unit queued or leased left: ready to settle and finish.
  std::vector<int64_t> enforce_time_budgets();

  /// Every lease -> queued, counted as expired: at server start, leases granted before the
  /// restart are void (their workers may be gone; their results will be dropped as stale).
  int revoke_all();

 private:
  /// Every lease expiring before `bound` -> queued, counted as expired.
  int requeue_expiring_before(int64_t bound);
  /// Records a failure of `unit_id` by `worker_id`; true when it failed the job.
  bool record_failure(int64_t unit_id, int64_t job_id, int64_t worker_id,
                      const std::string& message);

  Database& db_;
  UnitsTable units_;
  JobStore& jobs_;
  const Clock& clock_;
  int64_t lease_ms_;
  IdSource new_id_;
  WorkerHealthPolicy policy_;
};

}  // namespace tessera::server
