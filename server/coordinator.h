// The farm's coordinator: the server's parts wired together, behind the one interface the gRPC
// services and the dashboard call. Each part owns its state and its lock and reaches the store
// through FarmStore (server/farm_store.h), whose lock writes the leases answered from memory
// before any other store operation:
//   WorkerPresence (worker_presence.h)  registration, each call's check, online, health warnings
//   Leasing (leasing.h)                 leases and heartbeats from the lease book, release, expiry
//   ResultIntake (result_intake.h)      uploads decoded and merged in batch order, group commit
//   JobImages (job_images.h)            the output files when a job finishes, previews
//   JobLifecycle (job_lifecycle.h)      submit, read, cancel, delete, retention, priority, resume
//   FarmViews (farm_views.h)            tile maps and farm-wide totals for the dashboard
//   StoreHealth (store_health.h)        the whole-file check, readiness, the clean shutdown
// Protos are translated by the services; results are decoded, scenes parsed and images encoded
// outside the store's lock.
#pragma once

#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "clock.h"
#include "farm_events.h"
#include "farm_limits.h"
#include "farm_store.h"
#include "farm_views.h"
#include "job_images.h"
#include "job_lifecycle.h"
#include "leasing.h"
#include "result_intake.h"
#include "store_health.h"
#include "worker_presence.h"

namespace tessera::server {

struct CoordinatorConfig {
  std::string db_path = "var/tessera.db";        ///< ":memory:" in tests
  std::filesystem::path output_dir = "var/outputs";
  int64_t lease_ms = 30'000;                     ///< lease length; heartbeats extend it
  FarmLimits limits;                             ///< what a job may ask (docs/security.md)
  WorkerHealthPolicy health;                     ///< blocking and failing (docs/reliability.md)
  /// A worker whose NaN/Inf samples exceed this fraction of its samples is reported.
  double nan_report_fraction = 1e-3;
  /// Final jobs older than this many days are deleted (--retention-days); 0 = keep them.
  double retention_days = 0;
  /// Decoded tiles kept in memory between merges, at most this many bytes (--merge-cache-mb;
  /// server/merge_cache.h).
  size_t merge_cache_bytes = MergeCache::kDefaultBudgetBytes;
  /// A result held for a spot check merges unchecked after this long (--check-wait-s).
  int64_t check_wait_ms = SpotChecks::kDefaultWaitMs;
  /// Opens the output files (empty: ImageFileStream); tests inject a full disk here.
  ImageFileOpener output_opener;
  /// Called with the store's connection once the coordinator is built (the store opened and
  /// migrated); tests make the store's disk full through it (PRAGMA max_page_count). Empty in
  /// the server.
  std::function<void(Database&)> on_store_open;
  /// Denoises the jobs that ask for it (server/job_denoise.h); null: such jobs are refused.
  std::shared_ptr<JobDenoise> denoise;
  /// Called as each upload group's commit begins, before it takes the store lock, with the
  /// number of results the group holds (tests line calls up here); empty in the server.
  std::function<void(size_t results)> before_upload_commit;
};

/// Each call is the named part's; its contract is written there.
class Coordinator {
 public:
  /// Opens (creating) the database and applies migrations (FarmStore), and starts the
  /// whole-file check in the background when the last server did not shut down cleanly
  /// (StoreHealth). Throws StoreCorrupt for a database damaged where start-up reads it,
  /// SqliteError for other store errors.
  Coordinator(const CoordinatorConfig& config, const Clock& clock);

  // ---- Jobs (JobLifecycle, JobImages) ------------------------------------------------------
  int resume() { return lifecycle_.resume(); }
  JobRecord submit(const v1::SceneBundle& bundle, const v1::JobRequestOptions& options,
                   int priority, const std::string& client = "") {
    return lifecycle_.submit(bundle, options, priority, client);
  }
  JobRecord job(int64_t job_id);
  JobPage jobs(const JobQuery& query);
  /// The newest `limit` jobs.
  std::vector<JobRecord> jobs(uint32_t limit) {
    JobQuery query;
    query.limit = limit;
    return jobs(query).jobs;
  }
  JobRecord cancel(int64_t job_id) { return lifecycle_.cancel(job_id); }
  void remove(int64_t job_id) { lifecycle_.remove(job_id); }
  int apply_retention() { return lifecycle_.apply_retention(); }
  JobRecord set_priority(int64_t job_id, int priority) {
    return lifecycle_.set_priority(job_id, priority);
  }
  std::string bundle(const std::string& sha256) { return lifecycle_.bundle(sha256); }
  JobImage image(int64_t job_id, const std::string& format, bool denoised = false) {
    return images_.image(job_id, format, denoised);
  }
  /// From memory, no store read: whether the job may still change state (queued or running:
  /// in the lease book); false once it ended (done, failed, cancelled, deleted) or if unknown.
  bool job_in_progress(int64_t job_id) { return store_.book().has_job(job_id); }

  /// Sets waiting_for_build on the jobs pinned to a build no online worker has.
  void note_waiting_for_build(std::vector<JobRecord>& jobs);
  /// Sets the jobs' spot-check counters (SpotChecks, since the start).
  void note_checks(std::vector<JobRecord>& jobs);

  // ---- Workers (WorkerPresence) --------------------------------------------------------------
  std::vector<WorkerRecord> workers() { return presence_.workers(); }
  bool online(const WorkerRecord& worker) const { return presence_.online(worker); }
  int64_t register_worker(const WorkerRegistration& info) {
    return presence_.register_worker(info);
  }
  void deregister(int64_t worker_id) { presence_.deregister(worker_id); }

  // ---- Leases (Leasing) ----------------------------------------------------------------------
  static constexpr size_t kMaxDelivering = Leasing::kMaxDelivering;
  static constexpr size_t kMaxLeasesPerHeartbeat = Leasing::kMaxLeasesPerHeartbeat;
  /// One unit (lease_units with max_units 1); nullopt: no work.
  std::optional<LeasedUnit> lease(int64_t worker_id, std::chrono::milliseconds wait,
                                  const std::function<bool()>& cancelled);
  std::vector<LeasedUnit> lease_units(int64_t worker_id, uint32_t max_units,
                                      std::chrono::milliseconds wait,
                                      const std::function<bool()>& cancelled,
                                      const std::vector<std::string>& delivering = {}) {
    return leasing_.lease_units(worker_id, max_units, wait, cancelled, delivering);
  }
  std::optional<int64_t> heartbeat(int64_t worker_id, const std::string& lease_id) {
    return leasing_.heartbeat(worker_id, lease_id);
  }
  std::vector<std::optional<int64_t>> heartbeat_all(int64_t worker_id,
                                                    const std::vector<std::string>& lease_ids) {
    return leasing_.heartbeat_all(worker_id, lease_ids);
  }
  ReleaseOutcome release(int64_t worker_id, const std::string& lease_id, ReleaseReason reason,
                         const std::string& message) {
    return leasing_.release(worker_id, lease_id, reason, message);
  }
  /// Expired leases back to the queue, and the spot checks' bounded wait (sweep_checks).
  int expire_leases() {
    const int expired = leasing_.expire_leases();
    intake_.sweep_checks();
    return expired;
  }
  /// Ends the quarantine of the worker's name (server/spot_checks.h); returns the name. Throws
  /// FarmError: not_found for an unknown worker, failed_precondition when not quarantined.
  std::string release_worker(int64_t worker_id);
  /// Spot checks' counters since the start (server/spot_checks.h), and quarantined workers.
  CheckCounts check_totals() { return store_.checks().totals(); }
  size_t quarantined_workers() { return store_.checks().quarantined_count(); }
  /// Graceful shutdown, first step: no more leases (LeaseUnit answers "no work"), long polls
  /// and watches end. Uploads, heartbeats and releases still work, so results in flight commit.
  void stop_leasing() { events_.changes.stop(); }

  // ---- Results (ResultIntake) ----------------------------------------------------------------
  static constexpr size_t kResultsPerCommit = ResultIntake::kResultsPerCommit;
  AcceptOutcome upload(const UnitResult& result) { return upload_all({result}).front(); }
  std::vector<AcceptOutcome> upload_all(const std::vector<UnitResult>& results) {
    return intake_.upload_all(results);
  }
  /// Call before serving; the observer must outlive the coordinator's calls.
  void set_upload_observer(UploadObserver* observer) { intake_.set_observer(observer); }

  // ---- Dashboard views (FarmViews, StoreHealth) ----------------------------------------------
  TileMap tile_map(int64_t job_id) { return views_.tile_map(job_id); }
  FarmTotals totals() { return views_.totals(); }
  bool store_ready() { return health_.ready(); }
  /// Why the server is not ready on the store's side ("" when it is): StoreHealth.
  std::string store_unready_reason() { return health_.unready_reason(); }
  /// Why the store cannot write ("" when it can): StoreHealth::write_error.
  std::string store_write_error() { return health_.write_error(); }
  std::optional<IntegrityState> store_check() const { return health_.check(); }
  std::optional<double> store_check_progress() const { return health_.check_progress(); }
  std::optional<IntegrityState> wait_for_store_check() const { return health_.wait_for_check(); }
  std::string store_damage() const { return health_.damage(); }
  void set_damage_observer(std::function<void(const std::string&)> observer) {
    health_.set_damage_observer(std::move(observer));
  }
  /// Last step of a graceful shutdown (StoreHealth::checkpoint). Nothing may write after it.
  bool checkpoint() { return health_.checkpoint(); }

  ChangeNotifier& changes() { return events_.changes; }
  int64_t lease_ms() const { return store_.lease_ms(); }
  const Clock& clock() const { return clock_; }

  // ---- Counters for tests and BENCHMARKS.md --------------------------------------------------
  /// What the store has executed since the server started: the statements a lease or an
  /// accepted result costs (server/store/store_cost_test.cpp).
  StoreCounters store_counters();
  /// Leases granted from memory, and those of them void when written to the store (their job
  /// ended or tile closed first).
  uint64_t leases_granted() { return store_.book().granted(); }
  uint64_t leases_voided() { return store_.book().voided(); }
  /// Times the store's lock was taken (a lease takes it none).
  uint64_t store_lock_acquisitions() { return store_.mutex().acquisitions(); }
  size_t leases_held() { return store_.book().leases_held(); }
  /// Upload calls waiting for a group's commit, and the groups and calls committed so far.
  size_t upload_calls_waiting() { return intake_.calls_waiting(); }
  std::pair<uint64_t, uint64_t> upload_groups() { return intake_.groups(); }

 private:
  const Clock& clock_;
  FarmStore store_;
  FarmEvents events_;
  WorkerPresence presence_;
  JobImages images_;
  ResultIntake intake_;
  Leasing leasing_;
  JobLifecycle lifecycle_;
  FarmViews views_;
  /// Last, so that its check is stopped (its thread joined) before anything it calls is gone.
  StoreHealth health_;
};

}  // namespace tessera::server
