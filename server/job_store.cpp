#include "job_store.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "farm_error.h"
#include "store/results_table.h"
#include "store/tile_queue.h"
#include "store/units_table.h"

namespace tessera::server {
namespace {

std::string s(JobState state) { return std::string(to_string(state)); }
std::string s(UnitState state) { return std::string(to_string(state)); }

// Columns of a JobRecord, in the order read_job expects. ?1 is bound to 'leased'.
constexpr const char* kJobColumns = R"sql(
  j.id, j.state, j.priority, j.bundle_sha256, j.scene_file,
  j.width, j.height, j.spp, j.max_depth, j.seed, j.tile_size, j.batch_spp, j.isa,
  j.tile_count, j.batch_count, j.units_total,
  j.units_done, j.results_merged, j.results_dropped, j.leases_expired, j.units_released,
  j.samples_merged, j.nan_dropped, j.inf_dropped,
  j.submitted_unix_ms, j.started_unix_ms, j.finished_unix_ms, j.error, j.output_exr, j.output_png,
  (SELECT COUNT(*) FROM units u WHERE u.job_id = j.id AND u.state = ?1),
  (SELECT MIN(t.spp) FROM tiles t WHERE t.job_id = j.id),
  j.stop_rule, j.time_budget_ms, j.noise_target, j.budget_reached_unix_ms, j.stop_reason,
  j.units_skipped, j.results_wasted,
  (SELECT MAX(t.spp) FROM tiles t WHERE t.job_id = j.id),
  (SELECT AVG(t.spp) FROM tiles t WHERE t.job_id = j.id),
  (SELECT MAX(t.error) FROM tiles t WHERE t.job_id = j.id),
  (SELECT AVG(t.error) FROM tiles t WHERE t.job_id = j.id),
  (SELECT COUNT(*) FROM tiles t WHERE t.job_id = j.id AND t.finished != ''),
  NOT EXISTS (SELECT 1 FROM units u WHERE u.job_id = j.id AND u.state IN ('queued', 'leased'))
    AND NOT EXISTS (SELECT 1 FROM tile_queue q WHERE q.job_id = j.id
                    AND q.next_lease < q.lease_end),
  j.batch_schedule
)sql";

JobRecord read_job(const Statement& q) {
  JobRecord r;
  int c = 0;
  r.id = q.int64(c++);
  r.state = job_state_from_string(q.text(c++)).value_or(JobState::failed);
  r.priority = int(q.int64(c++));
  r.bundle_sha256 = q.text(c++);
  r.scene_file = q.text(c++);
  r.options.width = int(q.int64(c++));
  r.options.height = int(q.int64(c++));
  r.options.spp = uint32_t(q.int64(c++));
  r.options.max_depth = int(q.int64(c++));
  r.options.seed = uint64_t(q.int64(c++));
  r.options.tile_size = int(q.int64(c++));
  r.options.batch_spp = uint32_t(q.int64(c++));
  r.options.isa = q.text(c++);
  r.tile_count = uint32_t(q.int64(c++));
  r.batch_count = uint32_t(q.int64(c++));
  r.units_total = uint32_t(q.int64(c++));
  r.counters.units_done = uint32_t(q.int64(c++));
  r.counters.results_merged = uint32_t(q.int64(c++));
  r.counters.results_dropped = uint32_t(q.int64(c++));
  r.counters.leases_expired = uint32_t(q.int64(c++));
  r.counters.units_released = uint32_t(q.int64(c++));
  r.counters.samples_merged = uint64_t(q.int64(c++));
  r.counters.nan_dropped = uint64_t(q.int64(c++));
  r.counters.inf_dropped = uint64_t(q.int64(c++));
  r.submitted_unix_ms = q.int64(c++);
  r.started_unix_ms = q.int64(c++);
  r.finished_unix_ms = q.int64(c++);
  r.error = q.text(c++);
  r.output_exr = q.text(c++);
  r.output_png = q.text(c++);
  r.counters.units_leased = uint32_t(q.int64(c++));
  r.spp_merged = uint32_t(q.int64(c++));
  r.options.rule = stop_rule_from_string(q.text(c++)).value_or(StopRule::spp);
  r.options.time_budget_s = double(q.int64(c++)) / 1000.0;
  r.options.noise_target = q.real(c++);
  r.budget_reached_unix_ms = q.int64(c++);
  r.stop_reason = stop_reason_from_string(q.text(c++)).value_or(StopReason::none);
  r.counters.units_skipped = uint32_t(q.int64(c++));
  r.counters.results_wasted = uint32_t(q.int64(c++));
  r.reached.spp_min = r.spp_merged;
  r.reached.spp_max = uint32_t(q.int64(c++));
  r.reached.spp_mean = q.real(c++);
  r.reached.error_max = q.real(c++);
  r.reached.error_mean = q.real(c++);
  r.tiles_finished = uint32_t(q.int64(c++));
  r.complete = q.int64(c++) != 0;
  r.options.batch_kind = batch_kind_from_string(q.text(c++)).value_or(BatchKind::fixed);
  return r;
}

void read_contributors(Database& db, JobRecord& r) {
  {
    auto q = db.prepare("SELECT DISTINCT isa FROM job_contributors WHERE job_id = ? ORDER BY isa");
    q->bind(1, r.id);
    while (q->step()) r.isas.push_back(q->text(0));
  }
  auto q = db.prepare(
      "SELECT DISTINCT version FROM job_contributors WHERE job_id = ? ORDER BY version");
  q->bind(1, r.id);
  while (q->step()) r.versions.push_back(q->text(0));
}

}  // namespace

double JobRecord::progress() const {
  if (options.rule != StopRule::spp) {
    if (state == JobState::done || units_total == 0) return state == JobState::done ? 1.0 : 0.0;
    double settled = double(counters.units_done + counters.units_skipped) / units_total;
    if (options.rule == StopRule::time && options.time_budget_s > 0 && started_unix_ms > 0 &&
        read_unix_ms > started_unix_ms) {
      // A time job is mostly its budget: report the share of it used (it ends soon after).
      settled = std::max(settled, 0.99 * double(read_unix_ms - started_unix_ms) /
                                      (1000.0 * options.time_budget_s));
    }
    return std::min(settled, state == JobState::done ? 1.0 : 0.99);
  }
  const double asked = double(options.width) * double(options.height) * double(options.spp);
  if (asked <= 0) return 0;
  if (units_total > 0 && counters.results_merged == units_total) return 1.0;
  return std::min(1.0, double(counters.samples_merged) / asked);
}

double JobRecord::wall_time_s() const {
  if (started_unix_ms <= 0) return 0;
  const int64_t end = finished_unix_ms > 0 ? finished_unix_ms : read_unix_ms;
  return end > started_unix_ms ? double(end - started_unix_ms) / 1000.0 : 0.0;
}

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
  db_.prepare(
         "INSERT OR IGNORE INTO bundles (sha256, scene_file, data, size_bytes, created_unix_ms)"
         " VALUES (?, ?, ?, ?, ?)")
      ->bind(1, job.bundle_sha256)
      .bind(2, job.scene_file)
      .bind_blob(3, job.bundle_bytes)
      .bind(4, int64_t(job.bundle_bytes.size()))
      .bind(5, now)
      .run();
  const JobOptions& o = job.options;
  db_.prepare(R"sql(
      INSERT INTO jobs (state, priority, bundle_sha256, scene_file, width, height, spp, max_depth,
                        seed, tile_size, batch_spp, isa, tile_count, batch_count, units_total,
                        submitted_unix_ms, stop_rule, time_budget_ms, noise_target,
                        batch_schedule)
      VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?))sql")
      ->bind(1, s(JobState::queued))
      .bind(2, job.priority)
      .bind(3, job.bundle_sha256)
      .bind(4, job.scene_file)
      .bind(5, o.width)
      .bind(6, o.height)
      .bind(7, o.spp)
      .bind(8, o.max_depth)
      .bind(9, int64_t(o.seed))
      .bind(10, o.tile_size)
      .bind(11, o.batch_spp)
      .bind(12, o.isa)
      .bind(13, int64_t(tiles.size()))
      .bind(14, plan.batch_count())
      .bind(15, int64_t(units))
      .bind(16, now)
      .bind(17, std::string(to_string(o.rule)))
      .bind(18, int64_t(std::llround(o.time_budget_s * 1000.0)))
      .bind(19, o.noise_target)
      .bind(20, std::string(to_string(o.batch_kind)))
      .run();
  const int64_t job_id = db_.last_insert_rowid();
  for (size_t t = 0; t < tiles.size(); ++t) {
    db_.prepare("INSERT INTO tiles (job_id, tile, x0, y0, x1, y1) VALUES (?, ?, ?, ?, ?, ?)")
        ->bind(1, job_id)
        .bind(2, int64_t(t))
        .bind(3, tiles[t].x0)
        .bind(4, tiles[t].y0)
        .bind(5, tiles[t].x1)
        .bind(6, tiles[t].y1)
        .run();
  }
  // The units themselves come into being when leased (store/tile_queue.h).
  TileQueue(db_).create(job_id, uint32_t(tiles.size()), plan.batch_count());
  tx.commit();
  return job_id;
}

std::optional<JobRecord> JobStore::get(int64_t job_id) {
  std::optional<JobRecord> record;
  {
    auto q = db_.prepare(std::string("SELECT ") + kJobColumns + " FROM jobs j WHERE j.id = ?2");
    q->bind(1, s(UnitState::leased)).bind(2, job_id);
    if (q->step()) record = read_job(*q);
  }
  if (record) read_contributors(db_, *record);
  return record;
}

std::vector<JobRecord> JobStore::list(uint32_t limit) {
  std::vector<JobRecord> out;
  {
    auto q = db_.prepare(std::string("SELECT ") + kJobColumns +
                         " FROM jobs j ORDER BY j.id DESC LIMIT ?2");
    q->bind(1, s(UnitState::leased)).bind(2, int64_t(limit));
    while (q->step()) out.push_back(read_job(*q));
  }
  for (JobRecord& r : out) read_contributors(db_, r);
  return out;
}

std::vector<int64_t> JobStore::unfinished() {
  std::vector<int64_t> out;
  auto q = db_.prepare("SELECT id FROM jobs WHERE state IN (?, ?) ORDER BY id");
  q->bind(1, s(JobState::queued)).bind(2, s(JobState::running));
  while (q->step()) out.push_back(q->int64(0));
  return out;
}

std::vector<DoneOutput> JobStore::done_outputs() {
  std::vector<DoneOutput> out;
  auto q = db_.prepare("SELECT id, output_exr, output_png FROM jobs WHERE state = ? ORDER BY id");
  q->bind(1, s(JobState::done));
  while (q->step()) out.push_back({q->int64(0), q->text(1), q->text(2)});
  return out;
}

namespace {

/// Applies a job event as compare-and-set; returns the state reached or nullopt when the job is
/// unknown or the event is not allowed.
std::optional<JobState> apply_job_event(Database& db, int64_t job_id, JobEvent event,
                                        bool* found) {
  std::optional<JobState> from;
  {
    auto q = db.prepare("SELECT state FROM jobs WHERE id = ?");
    q->bind(1, job_id);
    if (q->step()) from = job_state_from_string(q->text(0));
  }
  if (found) *found = from.has_value();
  if (!from) return std::nullopt;
  const std::optional<JobState> to = next_state(*from, event);
  if (!to) return std::nullopt;
  db.prepare("UPDATE jobs SET state = ? WHERE id = ? AND state = ?")
      ->bind(1, s(*to))
      .bind(2, job_id)
      .bind(3, s(*from))
      .run();
  return db.changes() == 1 ? to : std::nullopt;
}

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

CancelOutcome JobStore::cancel(int64_t job_id, int64_t now) {
  Transaction tx(db_);
  bool found = false;
  if (!apply_job_event(db_, job_id, JobEvent::cancel, &found)) {
    return found ? CancelOutcome::already_final : CancelOutcome::not_found;
  }
  db_.prepare("UPDATE jobs SET finished_unix_ms = ?, stop_reason = ? WHERE id = ?")
      ->bind(1, now)
      .bind(2, std::string(to_string(StopReason::cancelled)))
      .bind(3, job_id)
      .run();
  cancel_units(db_, job_id);
  tx.commit();
  return CancelOutcome::cancelled;
}

DeleteOutcome JobStore::remove(int64_t job_id) {
  {
    Transaction tx(db_);
    std::optional<JobState> state;
    std::string bundle;
    {
      auto q = db_.prepare("SELECT state, bundle_sha256 FROM jobs WHERE id = ?");
      q->bind(1, job_id);
      if (q->step()) {
        state = job_state_from_string(q->text(0));
        bundle = q->text(1);
      }
    }
    if (!state) return DeleteOutcome::not_found;
    if (!is_final(*state)) return DeleteOutcome::not_final;
    // ON DELETE CASCADE removes tiles, units (and their failures), pending results, the job's
    // worker failures, contributors and client.
    db_.prepare("DELETE FROM jobs WHERE id = ? AND state = ?")
        ->bind(1, job_id)
        .bind(2, s(*state))
        .run();
    if (db_.changes() != 1) return DeleteOutcome::not_found;
    db_.prepare(
           "DELETE FROM bundles WHERE sha256 = ?1 AND NOT EXISTS"
           " (SELECT 1 FROM jobs WHERE bundle_sha256 = ?1)")
        ->bind(1, bundle)
        .run();
    tx.commit();
  }
  db_.exec("PRAGMA incremental_vacuum");
  return DeleteOutcome::deleted;
}

std::vector<int64_t> JobStore::finished_before(int64_t before) {
  std::vector<int64_t> out;
  auto q = db_.prepare(
      "SELECT id FROM jobs WHERE state IN (?, ?, ?) AND finished_unix_ms > 0"
      " AND finished_unix_ms < ? ORDER BY id");
  q->bind(1, s(JobState::done))
      .bind(2, s(JobState::failed))
      .bind(3, s(JobState::cancelled))
      .bind(4, before);
  while (q->step()) out.push_back(q->int64(0));
  return out;
}

bool JobStore::fail_in_transaction(int64_t job_id, const std::string& message, int64_t now) {
  if (!apply_job_event(db_, job_id, JobEvent::fail, nullptr)) return false;
  db_.prepare("UPDATE jobs SET finished_unix_ms = ?, error = ?, stop_reason = '' WHERE id = ?")
      ->bind(1, now)
      .bind(2, message)
      .bind(3, job_id)
      .run();
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
  std::optional<JobRecord> job;
  {
    auto q = db_.prepare(std::string("SELECT ") + kJobColumns + " FROM jobs j WHERE j.id = ?2");
    q->bind(1, s(UnitState::leased)).bind(2, job_id);
    if (q->step()) job = read_job(*q);
  }
  if (!job || job->state != JobState::running || !job->complete) return StopReason::none;
  // Results whose predecessor was skipped can never merge (only batch prefixes do).
  const int64_t wasted = ResultsTable(db_).drop_waiting_of_job(job_id);
  // A tile is closed by its verdict (noise target, cap, spp); a time job may leave tiles open.
  StopReason reason = StopReason::spp_reached;
  if (job->options.rule == StopRule::time) {
    reason = job->tiles_finished < job->tile_count ? StopReason::time_budget : StopReason::max_spp;
  } else if (job->options.rule == StopRule::noise) {
    auto q = db_.prepare("SELECT COUNT(*) FROM tiles WHERE job_id = ? AND finished = ?");
    q->bind(1, job_id).bind(2, std::string(to_string(StopReason::max_spp)));
    q->step();
    reason = q->int64(0) > 0 ? StopReason::max_spp : StopReason::noise_target;
  }
  db_.prepare("UPDATE jobs SET stop_reason = ?, results_wasted = results_wasted + ? WHERE id = ?")
      ->bind(1, std::string(to_string(reason)))
      .bind(2, wasted)
      .bind(3, job_id)
      .run();
  tx.commit();
  return reason;
}

bool JobStore::finish(int64_t job_id, const std::string& output_exr, const std::string& output_png,
                      int64_t now) {
  Transaction tx(db_);
  const JobState to = *next_state(JobState::running, JobEvent::finish);
  if (units_left(db_, job_id)) return false;
  db_.prepare(
         "UPDATE jobs SET state = ?, finished_unix_ms = ?, output_exr = ?, output_png = ?"
         " WHERE id = ? AND state = ?")
      ->bind(1, s(to))
      .bind(2, now)
      .bind(3, output_exr)
      .bind(4, output_png)
      .bind(5, job_id)
      .bind(6, s(JobState::running))
      .run();
  const bool finished = db_.changes() == 1;
  tx.commit();
  return finished;
}

std::vector<TileRecord> JobStore::tiles(int64_t job_id) {
  std::vector<TileRecord> out;
  auto q = db_.prepare(
      "SELECT tile, x0, y0, x1, y1, next_batch, accumulation, error, finished, spp FROM tiles"
      " WHERE job_id = ? ORDER BY tile");
  q->bind(1, job_id);
  while (q->step()) {
    TileRecord t;
    t.tile = uint32_t(q->int64(0));
    t.rect = {int(q->int64(1)), int(q->int64(2)), int(q->int64(3)), int(q->int64(4))};
    t.next_batch = uint32_t(q->int64(5));
    if (!q->is_null(6)) t.accumulation = q->blob(6);
    t.error = q->real(7);
    t.finished = stop_reason_from_string(q->text(8)).value_or(StopReason::none);
    t.spp = uint32_t(q->int64(9));
    out.push_back(std::move(t));
  }
  return out;
}

std::optional<JobSpec> JobStore::spec(int64_t job_id) {
  auto q = db_.prepare(
      "SELECT width, height, spp, max_depth, seed, tile_size, batch_spp, isa, stop_rule,"
      " time_budget_ms, noise_target, bundle_sha256, batch_schedule FROM jobs WHERE id = ?");
  q->bind(1, job_id);
  if (!q->step()) return std::nullopt;
  JobSpec spec;
  JobOptions& o = spec.options;
  o.width = int(q->int64(0));
  o.height = int(q->int64(1));
  o.spp = uint32_t(q->int64(2));
  o.max_depth = int(q->int64(3));
  o.seed = uint64_t(q->int64(4));
  o.tile_size = int(q->int64(5));
  o.batch_spp = uint32_t(q->int64(6));
  o.isa = q->text(7);
  o.rule = stop_rule_from_string(q->text(8)).value_or(StopRule::spp);
  o.time_budget_s = double(q->int64(9)) / 1000.0;
  o.noise_target = q->real(10);
  spec.bundle_sha256 = q->text(11);
  o.batch_kind = batch_kind_from_string(q->text(12)).value_or(BatchKind::fixed);
  return spec;
}

std::optional<TileRect> JobStore::tile_rect(int64_t job_id, uint32_t tile) {
  auto q = db_.prepare("SELECT x0, y0, x1, y1 FROM tiles WHERE job_id = ? AND tile = ?");
  q->bind(1, job_id).bind(2, tile);
  if (!q->step()) return std::nullopt;
  return TileRect{int(q->int64(0)), int(q->int64(1)), int(q->int64(2)), int(q->int64(3))};
}

std::optional<std::string> JobStore::bundle_bytes(const std::string& sha256) {
  auto q = db_.prepare("SELECT data FROM bundles WHERE sha256 = ?");
  q->bind(1, sha256);
  if (!q->step()) return std::nullopt;
  return q->blob(0);
}

}  // namespace tessera::server
