// A job's life from the caller's side: submitted (validated against the farm's limits, then
// queued), read, re-prioritised, cancelled, deleted with its files, deleted by the retention
// rule, and resumed at server start.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "farm_events.h"
#include "farm_limits.h"
#include "farm_store.h"
#include "job_images.h"
#include "store/job_record.h"
#include "result_intake.h"
#include "tessera/v1/job.pb.h"

namespace tessera::server {

class JobLifecycle {
 public:
  /// `retention_days`: final jobs older than this many days are deleted; 0 keeps them.
  JobLifecycle(FarmStore& store, FarmEvents& events, const Clock& clock, JobImages& images,
               ResultIntake& intake, const FarmLimits& limits, double retention_days)
      : store_(store),
        events_(events),
        clock_(clock),
        images_(images),
        intake_(intake),
        limits_(limits),
        retention_days_(retention_days) {}

  /// At server start: leases granted before are revoked (units back in the queue, counted as
  /// expired), jobs whose every unit is merged but whose output was not written are finished,
  /// and done jobs missing a file get it. Returns the number of unfinished jobs resumed.
  int resume();
  /// Validates the bundle (paths, parse_scene) and the options (resolve_job_options), then
  /// queues the job. Throws FarmError(invalid_argument) with the one-line reason; nothing is
  /// stored then. `client` identifies the submitter for the --max-queued-jobs quota (FarmError
  /// resource_exhausted when it has that many unfinished jobs).
  JobRecord submit(const v1::SceneBundle& bundle, const v1::JobRequestOptions& options,
                   int priority, const std::string& client);
  /// Throws FarmError(not_found). A done job whose output could not be written says why
  /// (JobRecord::output_error) and names no files.
  JobRecord job(int64_t job_id);
  /// As job(), one page of jobs, newest first (JobsTable::page).
  JobPage jobs(const JobQuery& query);
  /// The canonical bundle bytes. Throws FarmError(not_found).
  std::string bundle(const std::string& sha256);
  /// Throws FarmError: not_found, failed_precondition when already finished.
  JobRecord cancel(int64_t job_id);
  /// Deletes a final job and its output files (JobStore::remove). Throws FarmError: not_found,
  /// failed_precondition when it is queued or running (cancel it first).
  void remove(int64_t job_id);
  /// Deletes the final jobs that finished more than the retention period ago, at most once a
  /// minute; called by the LeaseReaper. Returns how many.
  int apply_retention();
  /// Changes the priority of a queued or running job (the scheduler reads it at the next
  /// lease). Throws FarmError: not_found, failed_precondition when the job is already final.
  JobRecord set_priority(int64_t job_id, int priority);

 private:
  /// The job a valid submission queues; throws FarmError(invalid_argument) for one that is not.
  NewJob validated(const v1::SceneBundle& bundle, const v1::JobRequestOptions& options,
                   int priority);
  /// Throws FarmError(resource_exhausted) when `client` has used its quota. Requires the lock.
  void check_quota(const std::string& client);

  FarmStore& store_;
  FarmEvents& events_;
  const Clock& clock_;
  JobImages& images_;
  ResultIntake& intake_;
  const FarmLimits limits_;
  const double retention_days_;
  int64_t last_retention_unix_ms_ = 0;  ///< guarded by the store's lock
};

}  // namespace tessera::server
