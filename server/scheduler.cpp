#include "scheduler.h"

#include <limits>
#include <string>

#include "store/tile_queue.h"

namespace tessera::server {
namespace {

std::string s(UnitState state) { return std::string(to_string(state)); }
std::string s(JobState state) { return std::string(to_string(state)); }

}  // namespace

const char* Scheduler::first_unit_sql(bool noise) {
  // Units back in the queue (expired or released leases) keep their row. Both forms walk the
  // units_queue index (job_id, state, batch, tile) in order and stop at the first row that
  // qualifies: no sort, no scan of the job's other queued units (EXPLAIN QUERY PLAN is checked
  // in tests/farm). The noise form looks up each candidate's tile by its primary key; CROSS
  // JOIN keeps units as the outer loop.
  static constexpr const char* kUniform = R"sql(
      SELECT u.id, u.tile, u.batch FROM units u WHERE u.job_id = ?1 AND u.state = ?2 AND u.batch < ?4
      ORDER BY u.batch, u.tile LIMIT 1)sql";
  static constexpr const char* kNoise = R"sql(
      SELECT u.id, u.tile, u.batch FROM units u
      CROSS JOIN tiles t ON t.job_id = u.job_id AND t.tile = u.tile
      WHERE u.job_id = ?1 AND u.state = ?2 AND u.batch < ?4 AND u.batch < t.next_batch + ?3
      ORDER BY u.batch, u.tile LIMIT 1)sql";
  return noise ? kNoise : kUniform;
}

std::optional<Scheduler::Pick> Scheduler::first_unit(int64_t job_id, bool noise,
                                                     bool over_budget) {
  // Past its budget a time job gets batch 0 only: every tile gets its first batch.
  const int64_t batch_limit = over_budget ? int64_t(1) : std::numeric_limits<int64_t>::max();
  std::optional<Pick> requeued;
  {
    auto q = db_.prepare(first_unit_sql(noise));
    q->bind(1, job_id).bind(2, s(UnitState::queued));
    if (noise) q->bind(3, kNoiseLookahead);
    q->bind(4, batch_limit);
    if (q->step()) requeued = Pick{q->int64(0), uint32_t(q->int64(1)), uint32_t(q->int64(2))};
  }
  // The first unit without a row; the earlier of the two in (batch, tile) order goes first.
  const std::optional<UnbornUnit> unborn =
      TileQueue(db_).first(job_id, noise ? kNoiseLookahead : 0, batch_limit);
  if (!unborn) return requeued;
  const Pick fresh{std::nullopt, unborn->tile, unborn->batch};
  if (!requeued) return fresh;
  const bool fresh_first = std::pair(fresh.batch, fresh.tile) < std::pair(requeued->batch,
                                                                          requeued->tile);
  return fresh_first ? fresh : requeued;
}

std::optional<Lease> Scheduler::lease_next(int64_t worker_id) {
  Transaction tx(db_);
  if (std::optional<Lease> held = leases_.held_by(worker_id)) {
    if (const auto expires = leases_.extend_in_transaction(worker_id, held->lease_id)) {
      held->expires_unix_ms = *expires;
    }
    tx.commit();
    return held;
  }
  // The jobs that may lease, in scheduling order (the jobs_schedule index); few at a time.
  struct Candidate {
    int64_t job_id;
    bool noise, over_budget;
  };
  std::vector<Candidate> candidates;
  {
    auto q = db_.prepare(R"sql(
        SELECT j.id, j.stop_rule = 'noise',
               j.stop_rule = 'time' AND j.started_unix_ms > 0
                 AND j.started_unix_ms + j.time_budget_ms <= ?3
        FROM jobs j
        WHERE j.state IN (?1, ?2)
          AND NOT EXISTS (SELECT 1 FROM job_worker_failures f
                          WHERE f.job_id = j.id AND f.worker_id = ?4 AND f.failures >= ?5
                            AND f.last_failure_unix_ms > ?6)
        ORDER BY j.priority DESC, j.submitted_unix_ms ASC, j.id ASC)sql");
    q->bind(1, s(JobState::queued))
        .bind(2, s(JobState::running))
        .bind(3, clock_.now_unix_ms())
        .bind(4, worker_id)
        .bind(5, leases_.health_policy().failures_to_block)
        .bind(6, leases_.forgiven_before_unix_ms());
    while (q->step()) candidates.push_back({q->int64(0), q->int64(1) != 0, q->int64(2) != 0});
  }
  std::optional<Pick> pick;
  int64_t job_id = 0;
  for (const Candidate& c : candidates) {
    pick = first_unit(c.job_id, c.noise, c.over_budget);
    job_id = c.job_id;
    if (pick) break;
  }
  if (!pick) return std::nullopt;  // rolls back: nothing written
  std::optional<Lease> lease =
      pick->unit_id ? leases_.grant_in_transaction(*pick->unit_id, worker_id)
                    : leases_.grant_unborn_in_transaction(job_id, pick->tile, pick->batch,
                                                          worker_id);
  if (lease) {
    // queued -> running on the first lease; a running job stays running (JobEvent::start).
    const JobState to = *next_state(JobState::queued, JobEvent::start);
    db_.prepare("UPDATE jobs SET state = ?, started_unix_ms = ? WHERE id = ? AND state = ?")
        ->bind(1, s(to))
        .bind(2, clock_.now_unix_ms())
        .bind(3, lease->job_id)
        .bind(4, s(JobState::queued))
        .run();
  }
  tx.commit();
  return lease;
}

std::vector<int64_t> Scheduler::enforce_time_budgets() {
  const int64_t now = clock_.now_unix_ms();
  Transaction tx(db_);
  std::vector<int64_t> over;
  {
    auto q = db_.prepare(R"sql(
        SELECT id FROM jobs
        WHERE state = ?1 AND stop_rule = 'time' AND started_unix_ms > 0
          AND started_unix_ms + time_budget_ms <= ?2)sql");
    q->bind(1, s(JobState::running)).bind(2, now);
    while (q->step()) over.push_back(q->int64(0));
  }
  std::vector<int64_t> complete;
  const UnitState skipped = *next_state(UnitState::queued, UnitEvent::skip);
  for (int64_t job_id : over) {
    // Batch 0 is never skipped: every tile gets it, even after the budget.
    db_.prepare("UPDATE units SET state = ? WHERE job_id = ? AND state = ? AND batch > 0")
        ->bind(1, s(skipped))
        .bind(2, job_id)
        .bind(3, s(UnitState::queued))
        .run();
    // ...and so are those without a row yet.
    const int64_t n = db_.changes() + TileQueue(db_).skip_after_first_batch(job_id);
    db_.prepare(
           "UPDATE jobs SET units_skipped = units_skipped + ?, budget_reached_unix_ms ="
           " CASE WHEN budget_reached_unix_ms = 0 THEN ? ELSE budget_reached_unix_ms END"
           " WHERE id = ?")
        ->bind(1, n)
        .bind(2, now)
        .bind(3, job_id)
        .run();
    if (!units_left(db_, job_id)) complete.push_back(job_id);
  }
  tx.commit();
  return complete;
}

}  // namespace tessera::server
