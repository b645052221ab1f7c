#include "job_store.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "farm_error.h"
#include "store/bundles_table.h"
#include "store/integrity.h"
#include "store/job_contributors_table.h"
#include "store/jobs_table.h"
#include "store/results_table.h"
#include "store/tile_queue.h"
#include "store/tiles_table.h"
#include "store/units_table.h"

namespace tessera::server {
namespace {

void read_contributors(Database& db, JobRecord& r) {
  JobContributorsTable contributors(db);
  r.isas = contributors.isas(r.id);
  r.versions = contributors.versions(r.id);
}

}  // namespace

int64_t JobStore::create(const NewJob& job, int64_t now) {
  const JobPlan plan = job.options.plan();
  // Checked before tiles() allocates anything: a 32768x32768 job in 1-pixel tiles is refused.
  const uint64_t tile_count = uint64_t((plan.width + plan.tile_size - 1) / plan.tile_size) *
                              uint64_t((plan.height + plan.tile_size - 1) / plan.tile_size);
  const uint64_t units = tile_count * plan.batch_count();
  if (units > kMaxUnitsPerJob) {
    throw FarmError(ErrorCode::invalid_argument,
                    "job has " + std::to_string(units) + " work units (" +
                        std::to_string(tile_count) + " tiles x " +
                        std::to_string(plan.batch_count()) + " batches), more than the limit of " +
                        std::to_string(kMaxUnitsPerJob) + ": use a larger --tile or --batch");
  }
  const std::vector<TileRect> tiles = plan.tiles();
  Transaction tx(db_);
  BundlesTable(db_).insert_once(job.bundle_sha256, job.scene_file, job.bundle_bytes, now);
  const int64_t job_id =
      JobsTable(db_).insert(job, uint32_t(tiles.size()), plan.batch_count(), units, now);
  TilesTable(db_).insert(job_id, tiles);
  // The units themselves come into being when leased (store/tile_queue.h).
  TileQueue(db_).create(job_id, uint32_t(tiles.size()), plan.batch_count());
  tx.commit();
  return job_id;
}

std::optional<JobRecord> JobStore::get(int64_t job_id) {
  std::optional<JobRecord> record = JobsTable(db_).get(job_id);
  if (record) read_contributors(db_, *record);
  return record;
}

JobPage JobStore::list(const JobQuery& query) {
  JobPage page = JobsTable(db_).page(query);
  for (JobRecord& r : page.jobs) read_contributors(db_, r);
  return page;
}

std::vector<int64_t> JobStore::unfinished() { return JobsTable(db_).unfinished(); }

std::vector<DoneOutput> JobStore::done_outputs() { return JobsTable(db_).done_outputs(); }

namespace {

/// Every unit of the job that could still run -> cancelled (leases revoked).
void cancel_units(Database& db, int64_t job_id) {
  UnitsTable(db).cancel_job(job_id);
  TileQueue(db).close_job(job_id);
  ResultsTable(db).drop_waiting_of_job(job_id);
}

}  // namespace

bool units_left(Database& db, int64_t job_id) {
  return UnitsTable(db).any_queued_or_leased(job_id) || TileQueue(db).any_open(job_id);
}

namespace {

/// The job's state when `event` may apply to it: nullopt with `found` false for an unknown
/// job, with `found` true when the state machine refuses the event (the job is final).
std::optional<JobState> state_for(Database& db, int64_t job_id, JobEvent event, bool* found) {
  const auto row = JobsTable(db).state_and_bundle(job_id);
  if (found) *found = row.has_value();
  if (!row || !next_state(row->first, event)) return std::nullopt;
  return row->first;
}

}  // namespace

CancelOutcome JobStore::cancel(int64_t job_id, int64_t now) {
  Transaction tx(db_);
  bool found = false;
  const std::optional<JobState> from = state_for(db_, job_id, JobEvent::cancel, &found);
  if (!from || !JobsTable(db_).cancel(job_id, *from, now)) {
    return found ? CancelOutcome::already_final : CancelOutcome::not_found;
  }
  cancel_units(db_, job_id);
  tx.commit();
  return CancelOutcome::cancelled;
}

DeleteOutcome JobStore::remove(int64_t job_id) {
  {
    Transaction tx(db_);
    JobsTable jobs(db_);
    const auto row = jobs.state_and_bundle(job_id);
    if (!row) return DeleteOutcome::not_found;
    const auto& [state, bundle] = *row;
    if (!is_final(state)) return DeleteOutcome::not_final;
    // ON DELETE CASCADE removes tiles, units (and their failures), results, the job's worker
    // failures, contributors and client.
    if (!jobs.remove(job_id, state)) return DeleteOutcome::not_found;
    BundlesTable(db_).remove_unused(bundle);
    tx.commit();
  }
  release_free_pages(db_);
  return DeleteOutcome::deleted;
}

std::vector<int64_t> JobStore::finished_before(int64_t before) {
  return JobsTable(db_).finished_before(before);
}

bool JobStore::fail_in_transaction(int64_t job_id, const std::string& message, int64_t now) {
  const std::optional<JobState> from = state_for(db_, job_id, JobEvent::fail, nullptr);
  if (!from || !JobsTable(db_).fail(job_id, *from, message, now)) return false;
  cancel_units(db_, job_id);
  return true;
}

bool JobStore::fail(int64_t job_id, const std::string& message, int64_t now) {
  Transaction tx(db_);
  const bool failed = fail_in_transaction(job_id, message, now);
  tx.commit();
  return failed;
}

StopReason JobStore::settle(int64_t job_id) {
  Transaction tx(db_);
  const std::optional<JobRecord> job = JobsTable(db_).get(job_id);
  if (!job || job->state != JobState::running || !job->complete) return StopReason::none;
  // Results whose predecessor was skipped can never merge (only batch prefixes do).
  const int64_t wasted = ResultsTable(db_).drop_waiting_of_job(job_id);
  // A tile is closed by its verdict (noise target, cap, spp); a time job may leave tiles open.
  StopReason reason = StopReason::spp_reached;
  if (job->options.rule == StopRule::time) {
    reason = job->tiles_finished < job->tile_count ? StopReason::time_budget : StopReason::max_spp;
  } else if (job->options.rule == StopRule::noise) {
    reason = TilesTable(db_).count_finished_by(job_id, StopReason::max_spp) > 0
                 ? StopReason::max_spp
                 : StopReason::noise_target;
  }
  JobsTable(db_).settle(job_id, reason, wasted);
  tx.commit();
  return reason;
}

bool JobStore::finish(int64_t job_id, const std::string& output_exr, const std::string& output_png,
                      int64_t now) {
  Transaction tx(db_);
  if (units_left(db_, job_id)) return false;
  const bool finished = JobsTable(db_).finish(job_id, output_exr, output_png, now);
  tx.commit();
  return finished;
}

std::vector<TileRecord> JobStore::tiles(int64_t job_id) { return TilesTable(db_).of_job(job_id); }

std::vector<TilePosition> JobStore::tile_positions(int64_t job_id) { return TilesTable(db_).positions(job_id); }

std::string JobStore::tile_checkpoint(int64_t job_id, uint32_t tile) {
  return TilesTable(db_).checkpoint(job_id, tile).value_or(std::string());
}

std::optional<JobSpec> JobStore::spec(int64_t job_id) { return JobsTable(db_).spec(job_id); }

std::optional<TileRect> JobStore::tile_rect(int64_t job_id, uint32_t tile) {
  return TilesTable(db_).rect(job_id, tile);
}

std::optional<std::string> JobStore::bundle_bytes(const std::string& sha256) {
  return BundlesTable(db_).bytes(sha256);
}

}  // namespace tessera::server
