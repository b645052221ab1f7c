#include "store/jobs_table.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <stdexcept>

namespace tessera::server {
namespace {

std::string s(JobState state) { return std::string(to_string(state)); }

// Columns of a JobRecord, in the order read_job expects. 'leased' is a literal, not a bound
// parameter: compared with a parameter, `u.state` matches the partial indexes on units (WHERE
// state = 'leased') only once bound, so SQLite compiled the whole statement again on every
// execution (StoreCounters::reprepares): 8 % of the server's CPU during a 512x512 job watched
// by one client (BENCHMARKS.md, "What a result and a job cost the server, counted").
constexpr const char* kJobColumns = R"sql(
  j.id, j.state, j.priority, j.bundle_sha256, j.scene_file,
  j.width, j.height, j.spp, j.max_depth, j.seed, j.tile_size, j.batch_spp, j.isa,
  j.tile_count, j.batch_count, j.units_total,
  j.units_done, j.results_merged, j.results_dropped, j.leases_expired, j.units_released,
  j.samples_merged, j.nan_dropped, j.inf_dropped,
  j.submitted_unix_ms, j.started_unix_ms, j.finished_unix_ms, j.error, j.output_exr, j.output_png,
  (SELECT COUNT(*) FROM units u WHERE u.job_id = j.id AND u.state = 'leased'),
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
  j.batch_schedule, j.any_build, j.pinned_build, j.verify_rate, j.denoise, j.guides
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
  r.any_build = q.int64(c++) != 0;
  if (!q.is_null(c)) r.pinned_build = q.text(c);
  ++c;
  r.verify_rate = q.real(c++);
  r.denoise = q.int64(c++) != 0;
  r.guides = q.int64(c++) != 0;
  return r;
}

int64_t read_id(const Statement& q) { return q.int64(0); }

std::optional<JobRecord> read_one(Database& db, int64_t job_id) {
  static const std::string sql =
      std::string("SELECT ") + kJobColumns + " FROM jobs j WHERE j.id = ?1";
  return db.prepare(sql)->bind_all(job_id).first_row(read_job);
}

}  // namespace

std::optional<JobRecord> JobsTable::get(int64_t job_id) { return read_one(db_, job_id); }

namespace {

/// The five slots of a state filter (?1..?5 of the statements below), one per job state: the
/// filter's states, the first one repeated in the slots left over, so that one statement serves
/// every filter. `states` is not empty.
std::array<std::string, 5> state_slots(std::vector<JobState> states) {
  std::sort(states.begin(), states.end());
  states.erase(std::unique(states.begin(), states.end()), states.end());
  std::array<std::string, 5> slots;
  for (size_t i = 0; i < slots.size(); ++i) slots[i] = s(states[i < states.size() ? i : 0]);
  return slots;
}

}  // namespace

JobPage JobsTable::page(const JobQuery& query) {
  // The page walks the primary key down from the cursor and stops after `limit` matches (so it
  // reads one more row to tell whether an older one is left). `+j.state` keeps SQLite off
  // jobs_schedule, whose (state, priority, ...) order would need every match of the state
  // sorted by id first; the count, which needs no order, uses that index.
  static const std::string every_sql = std::string("SELECT ") + kJobColumns +
                                       " FROM jobs j WHERE j.id < ?1 ORDER BY j.id DESC LIMIT ?2";
  static const std::string some_sql =
      std::string("SELECT ") + kJobColumns +
      " FROM jobs j WHERE j.id < ?6 AND +j.state IN (?1, ?2, ?3, ?4, ?5)"
      " ORDER BY j.id DESC LIMIT ?7";
  const int64_t before = query.before_id > 0 ? query.before_id : INT64_MAX;
  const int64_t rows = int64_t(query.limit) + 1;
  JobPage page;
  if (query.states.empty()) {
    page.jobs = db_.prepare(every_sql)->bind_all(before, rows).rows(read_job);
    page.total = uint64_t(*db_.prepare("SELECT COUNT(*) FROM jobs")->first_row(read_id));
  } else {
    const auto [a, b, c, d, e] = state_slots(query.states);
    page.jobs = db_.prepare(some_sql)->bind_all(a, b, c, d, e, before, rows).rows(read_job);
    page.total =
        uint64_t(*db_.prepare("SELECT COUNT(*) FROM jobs WHERE state IN (?1, ?2, ?3, ?4, ?5)")
                      ->bind_all(a, b, c, d, e)
                      .first_row(read_id));
  }
  if (page.jobs.size() > query.limit) {
    page.jobs.resize(query.limit);
    if (!page.jobs.empty()) page.next_before_id = page.jobs.back().id;
  }
  return page;
}

std::optional<JobSpec> JobsTable::spec(int64_t job_id) {
  auto q = db_.prepare(
      "SELECT width, height, spp, max_depth, seed, tile_size, batch_spp, isa, stop_rule,"
      " time_budget_ms, noise_target, bundle_sha256, batch_schedule, denoise FROM jobs"
      " WHERE id = ?");
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
  spec.guides = q->int64(13) != 0;
  return spec;
}

std::optional<std::pair<JobState, std::string>> JobsTable::state_and_bundle(int64_t job_id) {
  auto q = db_.prepare("SELECT state, bundle_sha256 FROM jobs WHERE id = ?");
  q->bind(1, job_id);
  if (!q->step()) return std::nullopt;
  const std::optional<JobState> state = job_state_from_string(q->text(0));
  if (!state) return std::nullopt;
  return std::pair(*state, q->text(1));
}

std::vector<int64_t> JobsTable::unfinished() {
  return db_.prepare("SELECT id FROM jobs WHERE state IN (?, ?) ORDER BY id")
      ->bind_all(s(JobState::queued), s(JobState::running))
      .rows(read_id);
}

std::vector<DoneOutput> JobsTable::done_outputs() {
  return db_
      .prepare("SELECT id, output_exr, output_png, denoise FROM jobs WHERE state = ? ORDER BY id")
      ->bind_all(s(JobState::done))
      .rows([](const Statement& r) {
        return DoneOutput{r.int64(0), r.text(1), r.text(2), r.int64(3) != 0};
      });
}

std::vector<int64_t> JobsTable::finished_before(int64_t before) {
  return db_
      .prepare(
          "SELECT id FROM jobs WHERE state IN (?, ?, ?) AND finished_unix_ms > 0"
          " AND finished_unix_ms < ? ORDER BY id")
      ->bind_all(s(JobState::done), s(JobState::failed), s(JobState::cancelled), before)
      .rows(read_id);
}

std::vector<int64_t> JobsTable::running_over_budget(int64_t now) {
  auto q = db_.prepare(R"sql(
      SELECT id FROM jobs
      WHERE state = ?1 AND stop_rule = 'time' AND started_unix_ms > 0
        AND started_unix_ms + time_budget_ms <= ?2)sql");
  return q->bind_all(s(JobState::running), now).rows(read_id);
}

std::map<std::string, JobStateTotals> JobsTable::totals_by_state() {
  std::map<std::string, JobStateTotals> out;
  auto q = db_.prepare(
      "SELECT state, COUNT(*), SUM(units_done), SUM(leases_expired), SUM(results_dropped), "
      "SUM(samples_merged) FROM jobs GROUP BY state");
  while (q->step()) {
    out[q->text(0)] = {uint64_t(q->int64(1)), uint64_t(q->int64(2)), uint64_t(q->int64(3)),
                       uint64_t(q->int64(4)), uint64_t(q->int64(5))};
  }
  return out;
}

int64_t JobsTable::insert(const NewJob& job, uint32_t tile_count, uint32_t batch_count,
                          uint64_t units_total, int64_t now) {
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
      .bind(13, int64_t(tile_count))
      .bind(14, batch_count)
      .bind(15, int64_t(units_total))
      .bind(16, now)
      .bind(17, std::string(to_string(o.rule)))
      .bind(18, int64_t(std::llround(o.time_budget_s * 1000.0)))
      .bind(19, o.noise_target)
      .bind(20, std::string(to_string(o.batch_kind)))
      .run();
  const int64_t id = db_.last_insert_rowid();
  // Its own statement, only when set: the insert above runs on every schema since version 7
  // (the migration tests make jobs on older schemas).
  if (job.any_build) db_.prepare("UPDATE jobs SET any_build = 1 WHERE id = ?")->bind(1, id).run();
  if (job.verify_rate > 0) {
    db_.prepare("UPDATE jobs SET verify_rate = ? WHERE id = ?")
        ->bind(1, job.verify_rate)
        .bind(2, id)
        .run();
  }
  if (job.denoise) {
    db_.prepare("UPDATE jobs SET denoise = 1, guides = ? WHERE id = ?")
        ->bind_all(int64_t(job.guides), id)
        .run();
  }
  return id;
}

namespace {

/// The state the job state machine gives `from` on `event`, as stored text; throws on a
/// transition it does not allow (a caller's bug, not a race).
std::string to_state(JobState from, JobEvent event) {
  const std::optional<JobState> to = next_state(from, event);
  if (!to) {
    throw std::logic_error("job event " + std::string(to_string(event)) + " from " +
                           std::string(to_string(from)));
  }
  return s(*to);
}

}  // namespace

bool JobsTable::start(int64_t job_id, int64_t now) {
  db_.prepare("UPDATE jobs SET state = ?, started_unix_ms = ? WHERE id = ? AND state = ?")
      ->bind(1, to_state(JobState::queued, JobEvent::start))
      .bind(2, now)
      .bind(3, job_id)
      .bind(4, s(JobState::queued))
      .run();
  return db_.changes() == 1;
}

std::optional<JobPin> JobsTable::pin_build(int64_t job_id, const std::string& build) {
  auto q = db_.prepare("SELECT any_build, pinned_build FROM jobs WHERE id = ?");
  q->bind(1, job_id);
  if (!q->step()) return std::nullopt;
  JobPin pin{q->int64(0) != 0, build};
  if (pin.any_build) return pin;
  if (!q->is_null(1)) {
    pin.build = q->text(1);
    return pin;
  }
  db_.prepare("UPDATE jobs SET pinned_build = ? WHERE id = ?")
      ->bind(1, build)
      .bind(2, job_id)
      .run();
  return pin;
}

bool JobsTable::cancel(int64_t job_id, JobState from, int64_t now) {
  db_.prepare(
         "UPDATE jobs SET state = ?, finished_unix_ms = ?, stop_reason = ?"
         " WHERE id = ? AND state = ?")
      ->bind(1, to_state(from, JobEvent::cancel))
      .bind(2, now)
      .bind(3, std::string(to_string(StopReason::cancelled)))
      .bind(4, job_id)
      .bind(5, s(from))
      .run();
  return db_.changes() == 1;
}

bool JobsTable::fail(int64_t job_id, JobState from, const std::string& message, int64_t now) {
  db_.prepare(
         "UPDATE jobs SET state = ?, finished_unix_ms = ?, error = ?, stop_reason = ''"
         " WHERE id = ? AND state = ?")
      ->bind(1, to_state(from, JobEvent::fail))
      .bind(2, now)
      .bind(3, message)
      .bind(4, job_id)
      .bind(5, s(from))
      .run();
  return db_.changes() == 1;
}

bool JobsTable::finish(int64_t job_id, const std::string& output_exr,
                       const std::string& output_png, int64_t now) {
  db_.prepare(
         "UPDATE jobs SET state = ?, finished_unix_ms = ?, output_exr = ?, output_png = ?"
         " WHERE id = ? AND state = ?")
      ->bind(1, to_state(JobState::running, JobEvent::finish))
      .bind(2, now)
      .bind(3, output_exr)
      .bind(4, output_png)
      .bind(5, job_id)
      .bind(6, s(JobState::running))
      .run();
  return db_.changes() == 1;
}

bool JobsTable::remove(int64_t job_id, JobState state) {
  db_.prepare("DELETE FROM jobs WHERE id = ? AND state = ?")
      ->bind(1, job_id)
      .bind(2, s(state))
      .run();
  return db_.changes() == 1;
}

bool JobsTable::set_priority(int64_t job_id, int priority) {
  db_.prepare("UPDATE jobs SET priority = ? WHERE id = ? AND state IN ('queued', 'running')")
      ->bind(1, priority)
      .bind(2, job_id)
      .run();
  return db_.changes() > 0;
}

void JobsTable::settle(int64_t job_id, StopReason reason, int64_t wasted) {
  db_.prepare("UPDATE jobs SET stop_reason = ?, results_wasted = results_wasted + ? WHERE id = ?")
      ->bind(1, std::string(to_string(reason)))
      .bind(2, wasted)
      .bind(3, job_id)
      .run();
}

void JobsTable::count_released(int64_t job_id) {
  db_.prepare("UPDATE jobs SET units_released = units_released + 1 WHERE id = ?")
      ->bind(1, job_id)
      .run();
}

void JobsTable::count_expired(int64_t job_id) {
  db_.prepare("UPDATE jobs SET leases_expired = leases_expired + 1 WHERE id = ?")
      ->bind(1, job_id)
      .run();
}

void JobsTable::count_dropped(int64_t job_id) {
  db_.prepare("UPDATE jobs SET results_dropped = results_dropped + 1 WHERE id = ?")
      ->bind(1, job_id)
      .run();
}

void JobsTable::count_skipped(int64_t job_id, int64_t units_skipped, int64_t results_wasted) {
  db_.prepare(
         "UPDATE jobs SET units_skipped = units_skipped + ?, results_wasted = results_wasted + ?"
         " WHERE id = ?")
      ->bind(1, units_skipped)
      .bind(2, results_wasted)
      .bind(3, job_id)
      .run();
}

void JobsTable::count_budget_reached(int64_t job_id, int64_t units_skipped, int64_t now) {
  db_.prepare(
         "UPDATE jobs SET units_skipped = units_skipped + ?, budget_reached_unix_ms ="
         " CASE WHEN budget_reached_unix_ms = 0 THEN ? ELSE budget_reached_unix_ms END"
         " WHERE id = ?")
      ->bind(1, units_skipped)
      .bind(2, now)
      .bind(3, job_id)
      .run();
}

void JobsTable::count_accepted(int64_t job_id, uint32_t units, const MergedCounts& merged) {
  db_.prepare(
         "UPDATE jobs SET units_done = units_done + ?, results_merged = results_merged + ?,"
         " samples_merged = samples_merged + ?, nan_dropped = nan_dropped + ?,"
         " inf_dropped = inf_dropped + ? WHERE id = ?")
      ->bind(1, units)
      .bind(2, merged.results)
      .bind(3, int64_t(merged.pixel_samples))
      .bind(4, int64_t(merged.nan))
      .bind(5, int64_t(merged.inf))
      .bind(6, job_id)
      .run();
}

}  // namespace tessera::server
