#include "scheduler.h"

#include <limits>
#include <string>

#include "store/jobs_table.h"
#include "store/tile_queue.h"

namespace tessera::server {

std::optional<Scheduler::Pick> Scheduler::first_unit(int64_t job_id, bool noise,
                                                     bool over_budget) {
  // Past its budget a time job gets batch 0 only: every tile gets its first batch.
  const int64_t batch_limit = over_budget ? int64_t(1) : std::numeric_limits<int64_t>::max();
  std::optional<Pick> requeued;
  if (const std::optional<RequeuedUnit> u =
          units_.first_requeued(job_id, noise ? kNoiseLookahead : 0, batch_limit)) {
    requeued = Pick{u->unit_id, u->tile, u->batch};
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
  std::vector<Lease> leases = lease_up_to(worker_id, 1);
  if (leases.empty()) return std::nullopt;
  return leases.front();
}

std::vector<Lease> Scheduler::lease_up_to(int64_t worker_id, uint32_t max_units) {
  Transaction tx(db_);
  std::vector<Lease> out;
  for (Lease held : units_.leased_to(worker_id)) {
    if (const auto expires = leases_.extend_in_transaction(worker_id, held.lease_id)) {
      held.expires_unix_ms = *expires;
    }
    out.push_back(held);
  }
  if (out.size() >= max_units) {
    tx.commit();
    return out;
  }
  // The jobs that may lease, in scheduling order (the jobs_schedule index); few at a time.
  JobsTable jobs(db_);
  std::vector<LeaseCandidate> candidates =
      jobs.lease_candidates(worker_id, clock_.now_unix_ms(),
                            leases_.health_policy().failures_to_block,
                            leases_.forgiven_before_unix_ms());
  bool changed = false;
  for (LeaseCandidate& c : candidates) {
    while (out.size() < max_units) {
      const std::optional<Pick> pick = first_unit(c.job_id, c.noise, c.over_budget);
      if (!pick) break;
      std::optional<Lease> lease =
          pick->unit_id
              ? leases_.grant_in_transaction(c.job_id, {*pick->unit_id, pick->tile, pick->batch},
                                             worker_id)
              : leases_.grant_unborn_in_transaction(c.job_id, pick->tile, pick->batch, worker_id);
      if (!lease) break;  // lost the compare-and-set: cannot happen under the coordinator's lock
      changed = true;
      out.push_back(*lease);
      if (c.queued) {
        // queued -> running on the first lease; a running job stays running (JobEvent::start).
        jobs.start(c.job_id, clock_.now_unix_ms());
        c.queued = false;
      }
    }
    if (out.size() >= max_units) break;
  }
  if (changed || !out.empty()) tx.commit();  // else rolls back: nothing written
  return out;
}

std::vector<int64_t> Scheduler::enforce_time_budgets() {
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

}  // namespace tessera::server
