// The jobs table: one row per job, its options, state and counters. Every statement on `jobs`
// is here. Each state change is one event of the job state machine (store/job_state.h) applied
// as compare-and-set (`... WHERE id = ? AND state = <from>`): it returns false when another call
// changed the job first. The counters are added in the transaction of the event they count
// (docs/farm.md, "Where the SQL lives"); the caller holds that transaction.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "store/job_record.h"
#include "store/sqlite.h"

namespace tessera::server {

/// What the merge of one result (and its waiting successors) adds to the job's counters.
struct MergedCounts {
  uint32_t results = 0;           ///< results merged (0: the result waits for its predecessor)
  uint64_t pixel_samples = 0;     ///< pixels * spp of each merged batch
  uint64_t nan = 0, inf = 0;      ///< samples the merged results dropped
};

/// The most jobs one page of a listing holds (JobService.ListJobs, /api/jobs): the default too.
inline constexpr uint32_t kMaxJobPage = 1000;

/// Which jobs a listing asks for (JobService.ListJobs, /api/jobs): newest first, one page.
struct JobQuery {
  std::vector<JobState> states;  ///< jobs in any of these states; empty = every state
  int64_t before_id = 0;         ///< only jobs with a smaller id (a page's cursor); 0 = none
  uint32_t limit = kMaxJobPage;  ///< at most this many jobs on the page, >= 1
};

/// One page of a listing. A cursor (before_id) is stable while jobs are submitted: a new job
/// has a larger id, so it never shifts a later page the way it would shift an offset.
struct JobPage {
  std::vector<JobRecord> jobs;  ///< newest first
  uint64_t total = 0;           ///< jobs in the query's states, on every page
  int64_t next_before_id = 0;   ///< the next page's before_id; 0 when no older job matches
};

/// Farm-wide sums over the jobs of one state (the dashboard's totals).
struct JobStateTotals {
  uint64_t jobs = 0, units_done = 0, leases_expired = 0, results_dropped = 0, samples_merged = 0;
};

/// Which renderer builds a job's leases may go to (JobsTable::pin_build).
struct JobPin {
  bool any_build = false;  ///< every build
  std::string build;       ///< otherwise this one
  bool admits(const std::string& worker_build) const { return any_build || build == worker_build; }
};

class JobsTable {
 public:
  explicit JobsTable(Database& db) : db_(db) {}

  // ---- Reads ---------------------------------------------------------------------------------
  /// The job with its counters and tile summary (contributors are JobContributorsTable's).
  std::optional<JobRecord> get(int64_t job_id);
  /// The query's page, newest first: walks the primary key down from `before_id`, so a page
  /// costs its rows whatever the number of jobs; `total` is one COUNT(*) over the states.
  JobPage page(const JobQuery& query);
  /// The options and bundle hash only (the lease path). nullopt when unknown.
  std::optional<JobSpec> spec(int64_t job_id);
  /// The job's state and bundle hash; nullopt when unknown.
  std::optional<std::pair<JobState, std::string>> state_and_bundle(int64_t job_id);
  /// Ids of queued and running jobs, oldest first.
  std::vector<int64_t> unfinished();
  /// Every done job's id and output paths.
  std::vector<DoneOutput> done_outputs();
  /// Ids of final jobs that finished before `before_unix_ms`, oldest first.
  std::vector<int64_t> finished_before(int64_t before_unix_ms);
  /// Running time jobs whose budget (from their first lease) is spent at `now_unix_ms`.
  std::vector<int64_t> running_over_budget(int64_t now_unix_ms);
  /// Sums per state name (states without jobs absent).
  std::map<std::string, JobStateTotals> totals_by_state();

  // ---- Events (compare-and-set) --------------------------------------------------------------
  /// A submit: a new queued job with `tile_count` tiles and `units_total` units. Returns its id.
  int64_t insert(const NewJob& job, uint32_t tile_count, uint32_t batch_count,
                 uint64_t units_total, int64_t now_unix_ms);
  /// JobEvent::start: queued -> running, its first lease at `now_unix_ms`.
  bool start(int64_t job_id, int64_t now_unix_ms);
  /// The job's renderer build pin after pinning it to `build` when it had none and is not
  /// any_build (its first lease: docs/design.md, "The determinism contract"); nullopt for an
  /// unknown job. A pin never moves.
  std::optional<JobPin> pin_build(int64_t job_id, const std::string& build);
  /// JobEvent::cancel (from `from`): -> cancelled at `now_unix_ms`, stop reason `cancelled`.
  bool cancel(int64_t job_id, JobState from, int64_t now_unix_ms);
  /// JobEvent::fail (from `from`): -> failed at `now_unix_ms` with `message`.
  bool fail(int64_t job_id, JobState from, const std::string& message, int64_t now_unix_ms);
  /// JobEvent::finish: running -> done at `now_unix_ms` with its output files.
  bool finish(int64_t job_id, const std::string& output_exr, const std::string& output_png,
              int64_t now_unix_ms);
  /// The job, when still in `state`, is deleted; ON DELETE CASCADE removes its tiles, units,
  /// results, failures, contributors and client.
  bool remove(int64_t job_id, JobState state);
  /// A queued or running job's priority; false when the job is unknown or final.
  bool set_priority(int64_t job_id, int priority);
  /// Why a complete job stops, and the results that were left waiting (wasted) at that.
  void settle(int64_t job_id, StopReason reason, int64_t wasted);

  // ---- Counters (in the transaction of the event they count) ---------------------------------
  void count_released(int64_t job_id);
  void count_expired(int64_t job_id);
  /// A result refused by its unit's compare-and-set (a stale or superseded lease).
  void count_dropped(int64_t job_id);
  /// Units the stopping rule made unneeded, and accepted results it left unmerged.
  void count_skipped(int64_t job_id, int64_t units_skipped, int64_t results_wasted);
  /// The time rule past the budget skipped `units_skipped`; the first call dates the budget.
  void count_budget_reached(int64_t job_id, int64_t units_skipped, int64_t now_unix_ms);
  /// `units` accepted results: units_done + units, and what their merges merged.
  void count_accepted(int64_t job_id, uint32_t units, const MergedCounts& merged);

 private:
  Database& db_;
};

}  // namespace tessera::server
