// Jobs, their bundles, tiles and units in the SQLite store: creation, reads, and the job-level
// transitions (cancel, fail, finish) applied through the state machine as compare-and-set.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "store/job_record.h"
#include "store/jobs_table.h"
#include "store/sqlite.h"
#include "store/tiles_table.h"

namespace tessera::server {

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
  /// One page of jobs, newest first, with their contributors (JobsTable::page).
  JobPage list(const JobQuery& query);
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
  /// Every tile's rectangle and merged prefix, in tile order, without the checkpoint bytes.
  std::vector<TilePosition> tile_positions(int64_t job_id);
  /// A tile's checkpoint bytes; empty when nothing was checkpointed.
  std::string tile_checkpoint(int64_t job_id, uint32_t tile);
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
