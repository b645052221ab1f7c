// The Coordinator's views for the dashboard (server/dashboard/): tile maps with error estimates,
// farm-wide totals, readiness, and the one dashboard action the gRPC API lacks (re-prioritise).
// Declared in the "Dashboard views" block of coordinator.h.
#include <array>

#include "accum/accumulation_codec.h"
#include "accum/film.h"
#include "coordinator.h"
#include "farm_error.h"
#include "store/jobs_table.h"
#include "store/migrations.h"
#include "store/units_table.h"
#include "store/workers_table.h"

namespace tessera::server {
namespace {

/// estimate_relative_error leaves out pixels with fewer than 2 samples and answers 0 when none
/// has them: the dashboard shows "no estimate yet" then, not a perfect 0.
bool has_two_samples(const Accumulation& a) {
  for (uint32_t n : a.count) {
    if (n >= 2) return true;
  }
  return false;
}

}  // namespace

TileMap Coordinator::tile_map(int64_t job_id) {
  JobRecord job;
  std::vector<TileRecord> tiles;
  {
    StoreLock lock(*this);
    std::optional<JobRecord> found = jobs_.get(job_id);
    if (!found) throw FarmError(ErrorCode::not_found, "no job " + std::to_string(job_id));
    job = std::move(*found);
    merger_.checkpoint_job(job_id);
    tiles = jobs_.tiles(job_id);
  }
  const JobPlan plan = job.options.plan();
  TileMap map;
  map.tiles.reserve(tiles.size());
  std::vector<Accumulation> merged;
  for (const TileRecord& t : tiles) {
    TileView v;
    v.tile = t.tile;
    v.rect = t.rect;
    v.batches_merged = t.next_batch;
    v.spp_merged = t.next_batch == 0 ? 0 : plan.batch_end(t.next_batch - 1);
    if (!t.accumulation.empty()) {
      merged.push_back(decode_accumulation(t.accumulation));
      if (has_two_samples(merged.back())) v.relative_error = estimate_relative_error({merged.back()});
    }
    map.tiles.push_back(v);
  }
  bool any = false;
  for (const Accumulation& a : merged) any = any || has_two_samples(a);
  if (any) map.relative_error = estimate_relative_error(merged);
  return map;
}

FarmTotals Coordinator::totals() {
  FarmTotals totals;
  for (JobState s : {JobState::queued, JobState::running, JobState::done, JobState::failed,
                     JobState::cancelled}) {
    totals.jobs_by_state[std::string(to_string(s))] = 0;
  }
  StoreLock lock(*this);
  for (const auto& [state, sums] : JobsTable(db_).totals_by_state()) {
    totals.jobs_by_state[state] = sums.jobs;
    totals.units_done += sums.units_done;
    totals.leases_expired += sums.leases_expired;
    totals.results_dropped += sums.results_dropped;
    totals.samples_merged += sums.samples_merged;
  }
  totals.units_leased_now = uint64_t(UnitsTable(db_).count_leased());
  totals.workers = uint64_t(WorkersTable(db_).count());
  return totals;
}

JobRecord Coordinator::set_priority(int64_t job_id, int priority) {
  JobRecord record;
  {
    StoreLock lock(*this);
    // Compare-and-set on the state: a job that ends meanwhile keeps its recorded priority.
    const bool changed = JobsTable(db_).set_priority(job_id, priority);
    std::optional<JobRecord> found = jobs_.get(job_id);
    if (!found) throw FarmError(ErrorCode::not_found, "no job " + std::to_string(job_id));
    if (!changed) {
      throw FarmError(ErrorCode::failed_precondition,
                      "job " + std::to_string(job_id) + " is already " +
                          std::string(to_string(found->state)));
    }
    book_.set_priority(job_id, priority);
    record = std::move(*found);
  }
  notify_changed(true);
  return record;
}

bool Coordinator::store_ready() {
  if (!store_damage().empty()) return false;
  try {
    StoreLock lock(*this);
    migrations_applied(db_);
    return true;
  } catch (const SqliteError&) {
    return false;
  }
}

}  // namespace tessera::server
