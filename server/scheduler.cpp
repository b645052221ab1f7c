#include "scheduler.h"

#include <string>

namespace tessera::server {

std::optional<Lease> Scheduler::lease_next(int64_t worker_id) {
  Transaction tx(db_);
  if (std::optional<Lease> held = leases_.held_by(worker_id)) {
    if (const auto expires = leases_.extend_in_transaction(worker_id, held->lease_id)) {
      held->expires_unix_ms = *expires;
    }
    tx.commit();
    return held;
  }
  // The scheduling query: the jobs_schedule index walks active jobs by (priority, age); for each
  // the units_queue index yields its first queued unit by (batch, tile).
  std::optional<int64_t> unit_id;
  {
    auto q = db_.prepare(R"sql(
        SELECT u.id
        FROM jobs j JOIN units u ON u.job_id = j.id AND u.state = ?1
        WHERE j.state IN (?2, ?3)
          AND NOT EXISTS (SELECT 1 FROM job_worker_failures f
                          WHERE f.job_id = j.id AND f.worker_id = ?4 AND f.failures >= ?5
                            AND f.last_failure_unix_ms > ?6)
        ORDER BY j.priority DESC, j.submitted_unix_ms ASC, j.id ASC, u.batch ASC, u.tile ASC
        LIMIT 1)sql");
    q->bind(1, std::string(to_string(UnitState::queued)))
        .bind(2, std::string(to_string(JobState::queued)))
        .bind(3, std::string(to_string(JobState::running)))
        .bind(4, worker_id)
        .bind(5, leases_.health_policy().failures_to_block)
        .bind(6, leases_.forgiven_before_unix_ms());
    if (q->step()) unit_id = q->int64(0);
  }
  if (!unit_id) return std::nullopt;  // rolls back: nothing written
  std::optional<Lease> lease = leases_.grant_in_transaction(*unit_id, worker_id);
  if (lease) {
    // queued -> running on the first lease; a running job stays running (JobEvent::start).
    const JobState to = *next_state(JobState::queued, JobEvent::start);
    db_.prepare("UPDATE jobs SET state = ?, started_unix_ms = ? WHERE id = ? AND state = ?")
        ->bind(1, std::string(to_string(to)))
        .bind(2, clock_.now_unix_ms())
        .bind(3, lease->job_id)
        .bind(4, std::string(to_string(JobState::queued)))
        .run();
  }
  tx.commit();
  return lease;
}

}  // namespace tessera::server
