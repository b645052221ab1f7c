// The farm's coordinator: one object owning the store and the components that act on it (job
// store, worker registry, lease table, scheduler, merger, output), serialising every store
// operation behind one mutex over one SQLite connection. Leases and heartbeats are answered
// from memory (server/lease_book.h) without that mutex; the leases granted are written to the
// store before any other store operation (flush_leases). The gRPC services translate protos
// and call it; it decodes results, parses scenes and encodes images outside the lock.
#pragma once

#include <atomic>
#include <chrono>
#include <filesystem>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "change_notifier.h"
#include "clock.h"
#include "farm_limits.h"
#include "group_commit.h"
#include "priority_mutex.h"
#include "job_output.h"
#include "job_store.h"
#include "lease_book.h"
#include "lease_table.h"
#include "store/integrity.h"
#include "store/sqlite.h"
#include "tessera/v1/job.pb.h"
#include "tile_merger.h"
#include "upload_observer.h"
#include "worker_registry.h"

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
  /// Opens the output files (empty: ImageFileStream); tests inject a full disk here.
  ImageFileOpener output_opener;
  /// Called as each upload group's commit begins, before it takes the store lock, with the
  /// number of results the group holds (tests line calls up here); empty in the server.
  std::function<void(size_t results)> before_upload_commit;
};

/// A tile of a job as the dashboard shows it (Coordinator::tile_map).
struct TileView {
  uint32_t tile = 0;
  TileRect rect;
  uint32_t batches_merged = 0;  ///< batches [0, batches_merged) are merged
  uint32_t spp_merged = 0;      ///< samples per pixel those batches cover
  /// estimate_relative_error (core/accum/film.h) of the merged sums; nullopt before 2 spp.
  std::optional<double> relative_error;
};

/// Every tile of a job, and the job's estimated relative error over all its merged pixels (the
/// figure `tessera-worker render` prints for the same sums; nullopt before 2 spp anywhere).
struct TileMap {
  std::vector<TileView> tiles;
  std::optional<double> relative_error;
};

/// Farm-wide totals from the store (Coordinator::totals), for /metrics.
struct FarmTotals {
  std::map<std::string, uint64_t> jobs_by_state;  ///< every state name, 0 when none
  uint64_t units_leased_now = 0;
  uint64_t units_done = 0;        ///< over all jobs, as stored
  uint64_t leases_expired = 0;
  uint64_t results_dropped = 0;
  uint64_t samples_merged = 0;
  uint64_t workers = 0;
};

struct JobImage {
  std::string bytes;
  bool final = false;
  uint32_t spp = 0;
  int width = 0, height = 0;
};

class Coordinator {
 public:
  /// Opens (creating) the database and applies migrations. Unless the last server left it with
  /// a clean shutdown (checkpoint()) or this start created it, starts the whole-file check (PRAGMA quick_check) in the
  /// background on its own connection (BackgroundIntegrityCheck) and returns without waiting
  /// for it: when it finds damage, the server logs it, stops leasing and is no longer ready
  /// (store_damage(), store_ready()). Throws StoreCorrupt for a database damaged where start-up
  /// reads it (the header, the schema), SqliteError for other store errors.
  Coordinator(const CoordinatorConfig& config, const Clock& clock);

  /// At server start: leases granted before are revoked (units back in the queue, counted as
  /// expired), and jobs whose every unit is merged but whose output was not written are
  /// finished. Returns the number of unfinished jobs resumed.
  int resume();

  /// Validates the bundle (paths, parse_scene) and the options (resolve_job_options), then
  /// queues the job. Throws FarmError(invalid_argument) with the one-line reason; nothing is
  /// stored then.
  /// `client` identifies the submitter for the --max-queued-jobs quota (FarmError
  /// resource_exhausted when it has that many unfinished jobs); every other limit of
  /// config.limits is FarmError(invalid_argument).
  JobRecord submit(const v1::SceneBundle& bundle, const v1::JobRequestOptions& options,
                   int priority, const std::string& client = "");
  /// Throws FarmError(not_found).
  JobRecord job(int64_t job_id);
  std::vector<JobRecord> jobs(uint32_t limit);
  /// Throws FarmError: not_found, failed_precondition when already finished.
  JobRecord cancel(int64_t job_id);
  /// Deletes a final job and its output files (JobStore::remove). Throws FarmError: not_found,
  /// failed_precondition when it is queued or running (cancel it first).
  void remove(int64_t job_id);
  /// Deletes the final jobs that finished more than `retention_days` ago (config; 0 = keep),
  /// at most once a minute; called by the LeaseReaper. Returns how many.
  int apply_retention();
  /// `format` is "exr" or "png". The final output when the job is done, else a preview.
  JobImage image(int64_t job_id, const std::string& format);

  std::vector<WorkerRecord> workers();
  /// True when the worker called within the last three lease periods.
  bool online(const WorkerRecord& worker) const;

  int64_t register_worker(const WorkerRegistration& info);
  /// The worker is stopping: online() is false for it until it calls again. Kept in memory
  /// (after a server restart a departed worker is offline three lease periods after its last
  /// call, as one that vanished).
  void deregister(int64_t worker_id);
  /// Leases a unit, waiting up to `wait` for one to appear (long poll) unless `cancelled()`
  /// says the caller went away. nullopt: no work. Every worker call throws
  /// FarmError(failed_precondition) for an unknown worker id (register again).
  std::optional<LeasedUnit> lease(int64_t worker_id, std::chrono::milliseconds wait,
                                  const std::function<bool()>& cancelled);
  /// Several units in one call (LeaseBook::lease_up_to): every lease the worker holds and new
  /// ones up to `max_units`, waiting as lease() does while there are none. Empty: no work.
  /// `delivering`: leases whose results the worker is delivering, left out (at most
  /// kMaxDelivering; more throws FarmError(invalid_argument)).
  std::vector<LeasedUnit> lease_units(int64_t worker_id, uint32_t max_units,
                                      std::chrono::milliseconds wait,
                                      const std::function<bool()>& cancelled,
                                      const std::vector<std::string>& delivering = {});
  /// Most leases a worker may name as delivering in one LeaseUnit call.
  static constexpr size_t kMaxDelivering = 64;
  /// The new expiry, or nullopt when the lease is not current.
  std::optional<int64_t> heartbeat(int64_t worker_id, const std::string& lease_id);
  /// Most lease ids one heartbeat may name.
  static constexpr size_t kMaxLeasesPerHeartbeat = 64;
  /// heartbeat() of several leases in one call and one transaction; answer i is lease i's.
  /// Throws FarmError(invalid_argument) for more than kMaxLeasesPerHeartbeat.
  std::vector<std::optional<int64_t>> heartbeat_all(int64_t worker_id,
                                                    const std::vector<std::string>& lease_ids);
  /// The canonical bundle bytes. Throws FarmError(not_found).
  std::string bundle(const std::string& sha256);
  /// Decodes and accepts a result; writes the job's output when it completes the job. Throws
  /// FarmError(invalid_argument) on bytes that do not decode or do not fit the unit.
  AcceptOutcome upload(const UnitResult& result);
  /// Several results of one worker in one transaction (TileMerger::accept_all); outcome i
  /// answers results[i]. All or nothing: FarmError(invalid_argument) naming the first result
  /// that does not decode or fit its unit, and nothing is stored. Calls that arrive while
  /// another commits share one transaction (group commit, server/group_commit.h); a call that
  /// fails in a group is retried alone, so one call's refusal never refuses another's.
  std::vector<AcceptOutcome> upload_all(const std::vector<UnitResult>& results);
  ReleaseOutcome release(int64_t worker_id, const std::string& lease_id, ReleaseReason reason,
                         const std::string& message);
  /// Returns expired leases' units to the queue and applies the time rule (jobs past their
  /// budget stop leasing; those with nothing in flight finish); called by the LeaseReaper.
  int expire_leases();

  /// Graceful shutdown, first step: no more leases (LeaseUnit answers "no work"), long polls
  /// and watches end. Uploads, heartbeats and releases still work, so results in flight commit.
  void stop_leasing() { changes_.stop(); }
  /// From memory, no store read: whether the job may still change state (queued or running:
  /// in the lease book); false once it ended (done, failed, cancelled, deleted) or if unknown.
  bool job_in_progress(int64_t job_id) { return book_.has_job(job_id); }
  /// Last step: stops the background check if it still runs, marks the store as shut down
  /// cleanly unless a check was due and did not end `ok` (so the next start checks again), and
  /// checkpoints the WAL into the database file (PRAGMA wal_checkpoint(TRUNCATE)).
  /// Returns false when the checkpoint could not complete. Nothing may write after it.
  bool checkpoint();

  // ---- Dashboard views (defined in server/coordinator_views.cpp, used by server/dashboard/) --
  /// Every tile of the job with what is merged and the error estimates (tiles are decoded
  /// outside the lock). Throws FarmError(not_found).
  TileMap tile_map(int64_t job_id);
  /// Farm-wide totals in one read of the store.
  FarmTotals totals();
  /// Changes the priority of a queued or running job (the scheduler reads it at the next
  /// lease). Throws FarmError: not_found, failed_precondition when the job is already final.
  JobRecord set_priority(int64_t job_id, int priority);
  /// True when the store answers a query and no damage was found (for /readyz).
  bool store_ready();
  // ---- end of dashboard views ---------------------------------------------------------------

  /// What the store has executed since the server started (StoreCounters): the statements a
  /// lease or an accepted result costs (tests/farm/store_cost_test.cpp, BENCHMARKS.md).
  StoreCounters store_counters();
  /// Leases granted from memory since the server started, and those of them void when written
  /// to the store (their job ended or tile closed first): tests and BENCHMARKS.md.
  uint64_t leases_granted() { return book_.granted(); }
  uint64_t leases_voided() { return book_.voided(); }
  /// Times the store's lock was taken since the server started (tests: a lease takes it none).
  uint64_t store_lock_acquisitions() const { return mu_.acquisitions(); }
  /// Leases the book holds now (tests).
  size_t leases_held() { return book_.leases_held(); }
  /// Upload calls waiting for a group's commit, and the groups and calls committed so far
  /// (tests: GroupCommit::waiting, GroupCommit::committed).
  size_t upload_calls_waiting() { return upload_commits_.waiting(); }
  std::pair<uint64_t, uint64_t> upload_groups() { return upload_commits_.committed(); }

  /// Every answered upload is reported to `observer` (the dashboard's counters). Call before
  /// serving; nullptr reports nothing. The observer must outlive the coordinator's calls.
  void set_upload_observer(UploadObserver* observer) { upload_observer_ = observer; }

  /// The whole-file check of this start: nullopt when none was due (the last server stopped
  /// cleanly), else its state.
  std::optional<IntegrityState> store_check() const;
  /// How much of the file the check has read, 0..1 (BackgroundIntegrityCheck::progress);
  /// nullopt when none was due.
  std::optional<double> store_check_progress() const;
  /// Blocks until the check of this start has ended (tests); nullopt when none was due.
  std::optional<IntegrityState> wait_for_store_check() const;
  /// The damage the check found (one line naming the file and what SQLite found), or "".
  std::string store_damage() const;
  /// `observer` is called once with store_damage() when the check finds damage, from the
  /// check's thread (at once, from this one, when it already has); it must not call back into
  /// the coordinator. Replacing it (nullptr) waits for a call in progress, so an observer is
  /// never called after it was replaced.
  void set_damage_observer(std::function<void(const std::string&)> observer);

  ChangeNotifier& changes() { return changes_; }
  int64_t lease_ms() const { return leases_.lease_ms(); }
  const Clock& clock() const { return clock_; }

 private:
  /// Writes the output of a fully merged job and marks it done (or failed with the reason).
  void finish_job(int64_t job_id);
  /// Reads a job's tile checkpoints for JobOutput::write, each under the store lock.
  TileCheckpointReader checkpoint_reader(int64_t job_id);
  /// Writes a done job's output files again when one is missing (a full disk when it finished,
  /// or a file removed since). Failures are logged: the image stays in the store.
  void rewrite_missing_output(const JobRecord& record);
  /// mu_, with the lease book's journal written to the store first (flush_leases): whatever
  /// the holder reads or changes in the store sees every lease answered before it.
  class StoreLock {
   public:
    explicit StoreLock(Coordinator& c) : lock_(c.mu_) { c.flush_leases(); }

   private:
    std::lock_guard<PriorityMutex> lock_;
  };
  /// Writes the leases the book granted since the last call (and the workers' last calls) in
  /// one transaction; a lease the store refuses is void. Requires mu_. On a store error the
  /// journal is kept for the next call and the error is thrown.
  void flush_leases();
  /// The book's copy of the job, read again from the store (rare events: release, expiry,
  /// submit, resume). Requires mu_ and the journal written.
  void reload_job(int64_t job_id);
  /// A lease or heartbeat's check of the worker, in memory: departed_, the book's known
  /// workers (FarmError(failed_precondition) for an unknown one), its last call recorded.
  void touch_in_memory(int64_t worker_id, uint64_t call);
  /// Marks the worker seen by a call; throws FarmError(failed_precondition) for an unknown one.
  /// `call` is the call's number (begin_call(), taken when the call began): a call that began
  /// before the worker deregistered — a long poll still waiting — does not bring it back online.
  void touch_or_throw(int64_t worker_id, uint64_t call);
  void touch_or_throw(int64_t worker_id) { touch_or_throw(worker_id, begin_call()); }
  /// The rectangles of the results' tiles (nullopt: no such tile), each read once from the store
  /// and then kept (a tile never changes shape; job ids are never reused): an upload sizes its
  /// decode by them. Takes the store's lock only for a tile not kept yet; must not be called
  /// under tile_rects_mu_.
  std::vector<std::optional<TileRect>> tile_rects(const std::vector<UnitResult>& results);
  static constexpr size_t kTileRectsKept = size_t(1) << 16;  ///< then the map starts again
  /// Taken alone or inside mu_, never the other way round.
  std::mutex tile_rects_mu_;
  std::map<std::pair<int64_t, uint32_t>, TileRect> tile_rects_;  ///< guarded by tile_rects_mu_
  uint64_t begin_call() { return calls_begun_.fetch_add(1); }
  /// Logs, once per server run, a worker whose NaN/Inf share crossed the report threshold.
  void report_health(int64_t worker_id);

  /// One upload call waiting for its commit: its decoded results, then its outcomes or error.
  struct UploadCall {
    const std::vector<TileMerger::Upload>* uploads = nullptr;
    std::vector<AcceptOutcome> outcomes;
    std::exception_ptr error;
  };
  /// Commits a group of upload calls (GroupCommit's commit): one transaction for all, or, when
  /// that fails, one per call, each call getting its own outcome or error.
  void commit_uploads(const std::vector<UploadCall*>& calls);
  /// One call in its own transaction (under mu_).
  void commit_upload(UploadCall& call);

  const Clock& clock_;
  /// Guards db_ and every component below but book_. Upload groups take it Deferring
  /// (server/priority_mutex.h), everything else plainly; leases and heartbeats do not take it.
  /// A plain caller waits for at most PriorityMutex::kDeferringTurns group transactions (each
  /// group's start and each yield() is one) beyond the one in progress.
  PriorityMutex mu_;
  Database db_;
  JobStore jobs_;
  WorkerRegistry workers_;
  LeaseTable leases_;
  /// The leasable units and live leases in memory (own mutex; taken inside mu_, never the
  /// other way round).
  LeaseBook book_;
  TileMerger merger_;
  JobOutput output_;
  mutable std::mutex departed_mu_;
  /// Workers that deregistered and have not called since: worker id -> the number of calls
  /// begun when it deregistered (calls numbered from there on began after it).
  std::map<int64_t, uint64_t> departed_;
  std::atomic<uint64_t> calls_begun_{0};
  std::set<int64_t> finishing_;  ///< jobs whose output is being written (guarded by mu_)
  FarmLimits limits_;
  double nan_report_fraction_;
  std::set<int64_t> reported_workers_;  ///< NaN/Inf warning logged (guarded by mu_)
  /// When each worker's last_seen was last written (guarded by mu_): a call within
  /// touch_interval_ms() of it writes nothing (workers are never removed, so the worker exists).
  std::map<int64_t, int64_t> touched_unix_ms_;
  /// last_seen's granularity: an eighth of a lease, at most a second (online() allows three
  /// lease periods).
  int64_t touch_interval_ms() const { return std::min<int64_t>(1000, leases_.lease_ms() / 8); }
  double retention_days_;
  int64_t last_retention_unix_ms_ = 0;  ///< guarded by mu_
  ChangeNotifier changes_;  ///< anything a watcher shows changed (WatchJob, the dashboard)
  /// A unit may have become leasable: wakes long-polling LeaseUnit calls (a subset of changes_).
  ChangeNotifier work_;
  /// Notifies changes_, and work_ too when `work` (the change may let a unit be leased).
  void notify_changed(bool work) {
    changes_.notify();
    if (work) work_.notify();
  }
  /// Results committed together at most (GroupCommit's bound). A group yields between its calls
  /// to whoever waits for mu_ Urgent (commit_uploads; leases took it so before they moved to
  /// the lease book, and nothing does now). Every call of a group is answered when its
  /// transaction commits, so the group's workers come back at once, each with a lease and then
  /// an upload: the larger the group, the larger that crowd, and the leases in it wait for the
  /// CPU behind the uploads. Against 1024, 256 (16 calls of 16) cut the lease median 2-4x and
  /// about halved the lease p99 after each worker's first call at 64 simulated workers, and at
  /// 256 on a long job, for 5-10 % more server CPU per result; on a short job at 256 workers the
  /// first groups answer their workers into the start's crowd, and that p99 was worse in 7 of 12
  /// rounds (BENCHMARKS.md, "Lease latency and capacity"). 64 cost more CPU than it saved in lease
  /// latency when leases still waited for the store's lock.
  static constexpr size_t kResultsPerCommit = 256;
  GroupCommit<UploadCall> upload_commits_{
      [this](const std::vector<UploadCall*>& calls) { commit_uploads(calls); },
      [](const UploadCall& call) { return call.uploads->size(); }, kResultsPerCommit};
  UploadObserver* upload_observer_ = nullptr;  ///< set before serving; may be null
  std::function<void(size_t)> before_upload_commit_;  ///< CoordinatorConfig::before_upload_commit
  /// The check found damage: log it, stop leasing, tell the observer (from the check's thread).
  void store_damaged(const std::string& message);
  mutable std::mutex damage_mu_;
  std::string damage_;                                      ///< guarded by damage_mu_
  std::function<void(const std::string&)> damage_observer_;  ///< guarded by damage_mu_
  /// Last, so that it is stopped (its thread joined) before anything it calls is destroyed.
  std::unique_ptr<BackgroundIntegrityCheck> check_;
};

}  // namespace tessera::server
