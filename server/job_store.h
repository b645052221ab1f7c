// Jobs, their bundles, tiles and units in the SQLite store: creation, reads, and the job-level
// transitions (cancel, fail, finish) applied through the state machine as compare-and-set.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "accum/tile_rect.h"
#include "job/job_options.h"
#include "job/stopping_rule.h"
#include "job/tile_summary.h"
#include "job_state.h"
#include "store/sqlite.h"

namespace tessera::server {

/// Counters of a job (proto JobCounters documents each).
struct JobCounters {
  uint32_t units_done = 0;
  uint32_t units_leased = 0;
  uint32_t results_merged = 0;
  uint32_t results_dropped = 0;
  uint32_t leases_expired = 0;
  uint32_t units_released = 0;
  uint64_t samples_merged = 0;  ///< pixel samples merged: sum over merged units of pixels * spp
  uint64_t nan_dropped = 0;
  uint64_t inf_dropped = 0;
  uint32_t units_skipped = 0;   ///< units the stopping rule made unneeded (UnitEvent::skip)
  uint32_t results_wasted = 0;  ///< accepted results never merged (their tile had finished)
};

struct JobRecord {
  int64_t id = 0;
  JobState state = JobState::queued;
  int priority = 0;
  std::string bundle_sha256;
  std::string scene_file;
  JobOptions options;
  uint32_t tile_count = 0;
  uint32_t batch_count = 0;
  uint32_t units_total = 0;
  JobCounters counters;
  int64_t submitted_unix_ms = 0, started_unix_ms = 0, finished_unix_ms = 0;
  std::string error;
  std::string output_exr, output_png;
  uint32_t spp_merged = 0;           ///< minimum over tiles of samples per pixel merged
  TileSummary reached;               ///< spp and estimated error over tiles
  uint32_t tiles_finished = 0;       ///< tiles the stopping rule gives no more batches
  StopReason stop_reason = StopReason::none;  ///< set when the job ends (cancelled or done)
  int64_t budget_reached_unix_ms = 0;  ///< time rule: when leasing stopped (0 = not yet)
  bool complete = false;             ///< no unit queued or leased: ready to finish
  int64_t read_unix_ms = 0;          ///< when the record was read (for a running job's wall time)
  std::vector<std::string> isas;     ///< distinct ISAs of accepted results, sorted
  std::vector<std::string> versions; ///< distinct renderer versions of accepted results, sorted

  /// Samples merged over samples asked, in [0, 1]; exactly 1 when every unit is merged. For
  /// `noise` and `time` jobs, units settled (done or skipped) over units (a time job: at least
  /// the share of its budget used by read_unix_ms), below 1 until done.
  double progress() const;
  /// Seconds from the first lease to the end, or to read_unix_ms while running; 0 before.
  double wall_time_s() const;
};

/// A tile's merged state as stored.
struct TileRecord {
  uint32_t tile = 0;
  TileRect rect;
  uint32_t next_batch = 0;    ///< batches [0, next_batch) are merged
  uint32_t spp = 0;           ///< samples per pixel merged: the schedule's end of next_batch - 1
  std::string accumulation;   ///< encode_accumulation bytes; empty = nothing merged yet
  double error = 0;           ///< estimated relative error after the last merge
  StopReason finished = StopReason::none;  ///< the verdict that closed the tile; none = open
};

/// What a lease needs of its job: the resolved options and the bundle.
struct JobSpec {
  JobOptions options;
  std::string bundle_sha256;
};

/// Where a done job's output files are.
struct DoneOutput {
  int64_t job_id = 0;
  std::string exr, png;
};

struct NewJob {
  std::string bundle_sha256;
  std::string scene_file;
  std::string bundle_bytes;  ///< canonical serialization, stored once per hash
  JobOptions options;
  int priority = 0;
};

/// True while some unit of the job is queued or leased, with a row in `units` or still without
/// one (store/tile_queue.h): the job cannot finish yet.
bool units_left(Database& db, int64_t job_id);

enum class CancelOutcome { cancelled, not_found, already_final };
enum class DeleteOutcome { deleted, not_found, not_final };

class JobStore {
 public:
  /// Jobs with more units than this are refused at submit (raise --tile or --batch).
  static constexpr uint64_t kMaxUnitsPerJob = uint64_t(1) << 22;

  explicit JobStore(Database& db) : db_(db) {}

  /// Stores the bundle (once per hash), the job (queued) and its tiles, in one transaction:
  /// O(tiles) rows whatever the spp, the units come into being when leased
  /// (store/tile_queue.h). Returns the job id. Throws FarmError(invalid_argument) when the plan has more
  /// than kMaxUnitsPerJob units.
  int64_t create(const NewJob& job, int64_t now_unix_ms);

  std::optional<JobRecord> get(int64_t job_id);
  /// Newest first, at most `limit`.
  std::vector<JobRecord> list(uint32_t limit);
  /// Ids of jobs not final (queued or running), oldest first.
  std::vector<int64_t> unfinished();
  /// Every done job's id and output paths (jobs rows only: cheap at start-up).
  std::vector<DoneOutput> done_outputs();

  /// queued|running -> cancelled; its queued and leased units -> cancelled (leases revoked),
  /// pending results deleted. One transaction.
  CancelOutcome cancel(int64_t job_id, int64_t now_unix_ms);
  /// Removes a final (done, failed or cancelled) job with its tiles, units, pending results,
  /// failures, contributors and client, and its bundle when no other job uses it; then gives
  /// the freed pages back to the file system (PRAGMA incremental_vacuum). A queued or running
  /// job is left alone (not_final: cancel it first). The output files are the caller's.
  DeleteOutcome remove(int64_t job_id);
  /// Ids of final jobs that finished before `before_unix_ms` (for --retention-days).
  std::vector<int64_t> finished_before(int64_t before_unix_ms);
  /// queued|running -> failed with `message`; units cancelled. Call inside a transaction.
  /// Returns false when the job was already final.
  bool fail_in_transaction(int64_t job_id, const std::string& message, int64_t now_unix_ms);
  /// fail_in_transaction in its own transaction.
  bool fail(int64_t job_id, const std::string& message, int64_t now_unix_ms);
  /// For a running job with no unit queued or leased: drops the results still waiting for a
  /// skipped predecessor (counted as wasted) and records why the job stopped (its rule, its
  /// tiles' verdicts, its budget). Returns the reason; StopReason::none when the job is not
  /// running or not complete.
  StopReason settle(int64_t job_id);
  /// running -> done with the output files, only when no unit is queued or leased (every one
  /// merged, or skipped by the stopping rule). Returns false when the job was not running
  /// (cancelled meanwhile) or not complete.
  bool finish(int64_t job_id, const std::string& output_exr, const std::string& output_png,
              int64_t now_unix_ms);

  std::vector<TileRecord> tiles(int64_t job_id);
  /// The options and bundle of a job, without the counters (cheap: the lease path). nullopt
  /// when unknown.
  std::optional<JobSpec> spec(int64_t job_id);
  std::optional<TileRect> tile_rect(int64_t job_id, uint32_t tile);
  /// The canonical bundle bytes by hash; nullopt when unknown.
  std::optional<std::string> bundle_bytes(const std::string& sha256);

 private:
  Database& db_;
};

}  // namespace tessera::server
