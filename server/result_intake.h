// Results in: an upload's results are checked against their tiles and decoded outside the
// store's lock, then merged into their tiles in batch order (TileMerger) in one transaction
// shared with the uploads that arrive while another commits (group commit). The lease book
// follows what was merged, and a job whose last unit merged is handed to be finished.
#pragma once

#include <chrono>
#include <cstdint>
#include <exception>
#include <functional>
#include <map>
#include <mutex>
#include <set>
#include <optional>
#include <utility>
#include <vector>

#include "farm_events.h"
#include "farm_store.h"
#include "group_commit.h"
#include "tile_merger.h"
#include "upload_observer.h"
#include "worker_presence.h"

namespace tessera::server {

class ResultIntake {
 public:
  /// Called, outside the store's lock, for each job an upload completed (JobImages::finish_job).
  using FinishJob = std::function<void(int64_t job_id)>;
  /// CoordinatorConfig::before_upload_commit (tests line calls up there); may be empty.
  using BeforeCommit = std::function<void(size_t results)>;

  ResultIntake(FarmStore& store, WorkerPresence& presence, FarmEvents& events,
               const Clock& clock, size_t merge_cache_bytes, FinishJob finish_job,
               BeforeCommit before_commit)
      : store_(store),
        presence_(presence),
        events_(events),
        merger_(store.db(), clock, merge_cache_bytes),
        finish_job_(std::move(finish_job)),
        before_commit_(std::move(before_commit)) {}

  /// Several results of one worker in one transaction (TileMerger::accept_all); outcome i
  /// answers results[i]. All or nothing: FarmError(invalid_argument) naming the first result
  /// that does not decode or fit its unit, and nothing is stored. Calls that arrive while
  /// another commits share one transaction (group commit, server/group_commit.h); a call that
  /// fails in a group is retried alone, so one call's refusal never refuses another's.
  std::vector<AcceptOutcome> upload_all(const std::vector<UnitResult>& results);

  /// Writes the job's merged sums as its tiles' checkpoints (TileMerger::checkpoint_job).
  /// Requires the store's lock.
  void checkpoint_job(int64_t job_id) { merger_.checkpoint_job(job_id); }
  /// Forgets a deleted job's tiles. Requires the store's lock.
  void forget_job(int64_t job_id);

  /// The spot checks' bounded wait and expired check leases (SpotChecks::sweep): held results
  /// due merge unchecked. Called by the lease reaper (spot_check_intake.cpp).
  void sweep_checks();

  /// Every answered upload is reported to `observer`; nullptr reports nothing.
  void set_observer(UploadObserver* observer) { observer_ = observer; }
  /// Upload calls waiting for a group's commit, and the groups and calls committed so far.
  size_t calls_waiting() { return commits_.waiting(); }
  std::pair<uint64_t, uint64_t> groups() { return commits_.committed(); }

  /// Results committed together at most (GroupCommit's bound). A group yields between its calls
  /// to whoever waits for the store's lock Urgent (nothing does since leases moved to the lease
  /// book). Every call of a group is answered when its transaction commits, so the group's
  /// workers come back at once, each with a lease and then an upload: the larger the group, the
  /// larger that crowd, and the leases in it wait for the CPU behind the uploads. Against 1024,
  /// 256 (16 calls of 16) cut the lease median 2-4x and about halved the lease p99 after each
  /// worker's first call at 64 simulated workers, and at 256 on a long job, for 5-10 % more
  /// server CPU per result; on a short job at 256 workers the first groups answer their workers
  /// into the start's crowd, and that p99 was worse in 7 of 12 rounds (BENCHMARKS.md, "Lease
  /// latency and capacity"). 64 cost more CPU than it saved in lease latency when leases still
  /// waited for the store's lock.
  static constexpr size_t kResultsPerCommit = 256;

 private:
  /// One upload call waiting for its commit: its decoded results, then its outcomes or error.
  struct UploadCall {
    const std::vector<TileMerger::Upload>* uploads = nullptr;
    std::vector<AcceptOutcome> outcomes;
    std::exception_ptr error;
  };
  /// The results' tiles' pixel counts, checked from memory; FarmError(not_found) for a result
  /// of no unit.
  std::vector<int64_t> tile_pixels(const std::vector<UnitResult>& results);
  /// The rectangles of the results' tiles (nullopt: no such tile), each read once from the store
  /// and then kept (a tile never changes shape; job ids are never reused): an upload sizes its
  /// decode by them. Takes the store's lock only for a tile not kept yet; must not be called
  /// under tile_rects_mu_.
  std::vector<std::optional<TileRect>> tile_rects(const std::vector<UnitResult>& results);
  /// Reports the answered call to the observer, records the worker's rate from its accepted
  /// results (WorkerRates), wakes watchers (and idle workers when a merge may have freed work)
  /// and finishes the jobs it completed.
  void answered(const std::vector<TileMerger::Upload>& uploads,
                const std::vector<AcceptOutcome>& outcomes, double seconds);
  /// Commits the uploads (group commit) and answers them; throws the call's error.
  std::vector<AcceptOutcome> commit_and_answer(const std::vector<TileMerger::Upload>& uploads,
                                               std::chrono::steady_clock::time_point received);
  // ---- Spot checks (spot_check_intake.cpp) ----
  /// upload_all for a call with results SpotChecks routes (held, compared, dropped).
  std::vector<AcceptOutcome> upload_checked(const std::vector<UnitResult>& results,
                                            std::vector<Accumulation>& decoded,
                                            std::chrono::steady_clock::time_point received);
  /// Merges results released by the checks; their leases go back to the queue if that fails.
  void merge_released(std::vector<HeldResult>& released,
                      std::chrono::steady_clock::time_point received);
  /// Stores new quarantines, starts their workers' tiles in unfinished jobs again
  /// (redo_tiles_of) and hands back the leases the routing let go; wakes idle workers.
  void apply_checks(const SpotChecks::Routing& routing);
  /// Every tile of a queued or running job with a unit the worker's name delivered starts again
  /// from zero (store/tile_redo.h); returns their jobs (reload them). Requires the lock.
  std::set<int64_t> redo_tiles_of(const std::string& worker_name);
  /// Commits a group of upload calls (GroupCommit's commit): one transaction for all, or, when
  /// that fails, one per call, each call getting its own outcome or error.
  void commit_uploads(const std::vector<UploadCall*>& calls);
  /// The calls from `next` on in one transaction, which may end between two calls when a lease
  /// waits for the lock; returns the first call not committed. Requires the lock.
  size_t commit_together(const std::vector<UploadCall*>& calls, size_t next);
  /// One call in its own transaction. Requires the lock.
  void commit_upload(UploadCall& call);
  /// The lease book and the workers' health follow the committed calls. Requires the lock.
  void follow_merges(const std::vector<UploadCall*>& calls);

  FarmStore& store_;
  WorkerPresence& presence_;
  FarmEvents& events_;
  TileMerger merger_;  ///< requires the store's lock
  FinishJob finish_job_;
  BeforeCommit before_commit_;
  UploadObserver* observer_ = nullptr;  ///< set before serving; may be null
  static constexpr size_t kTileRectsKept = size_t(1) << 16;  ///< then the map starts again
  /// Taken alone or inside the store's lock, never the other way round.
  std::mutex tile_rects_mu_;
  std::map<std::pair<int64_t, uint32_t>, TileRect> tile_rects_;  ///< guarded by tile_rects_mu_
  GroupCommit<UploadCall> commits_{
      [this](const std::vector<UploadCall*>& calls) { commit_uploads(calls); },
      [](const UploadCall& call) { return call.uploads->size(); }, kResultsPerCommit};
};

}  // namespace tessera::server
