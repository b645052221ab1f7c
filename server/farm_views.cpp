#include "farm_views.h"

#include "accum/accumulation_codec.h"
#include "accum/film.h"
#include "farm_error.h"
#include "store/job_state.h"
#include "store/jobs_table.h"
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

TileMap FarmViews::tile_map(int64_t job_id) {
  JobRecord job;
  std::vector<TileRecord> tiles;
  {
    FarmStore::ReadLock lock(store_);
    std::optional<JobRecord> found = store_.jobs().get(job_id);
    if (!found) throw job_not_found(job_id);
    job = std::move(*found);
    try {
      intake_.checkpoint_job(job_id);
    } catch (const SqliteError&) {
      // The store cannot write (a full disk): the map shows each tile's error as of its last
      // checkpoint rather than failing (docs/reliability.md, "A full disk").
    }
    tiles = store_.jobs().tiles(job_id);
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
      if (has_two_samples(merged.back())) {
        v.relative_error = estimate_relative_error({merged.back()});
      }
    }
    map.tiles.push_back(v);
  }
  bool any = false;
  for (const Accumulation& a : merged) any = any || has_two_samples(a);
  if (any) map.relative_error = estimate_relative_error(merged);
  return map;
}

FarmTotals FarmViews::totals() {
  FarmTotals totals;
  for (JobState s : {JobState::queued, JobState::running, JobState::done, JobState::failed,
                     JobState::cancelled}) {
    totals.jobs_by_state[std::string(to_string(s))] = 0;
  }
  FarmStore::ReadLock lock(store_);
  for (const auto& [state, sums] : JobsTable(store_.db()).totals_by_state()) {
    totals.jobs_by_state[state] = sums.jobs;
    totals.units_done += sums.units_done;
    totals.leases_expired += sums.leases_expired;
    totals.results_dropped += sums.results_dropped;
    totals.samples_merged += sums.samples_merged;
  }
  totals.units_leased_now = uint64_t(UnitsTable(store_.db()).count_leased());
  totals.workers = uint64_t(WorkersTable(store_.db()).count());
  return totals;
}

}  // namespace tessera::server
