// The lease book: the leasable units and the live leases of the unfinished jobs, in memory, so that
// a LeaseUnit or Heartbeat call takes no store lock and runs no SQL statement, and a lease never
// waits for uploads (BENCHMARKS.md, "Lease latency and capacity"). A lease need not be durable:
// after a server crash every lease is void (docs/reliability.md), so the store learns of a lease
// after it was answered. The book keeps a journal of the leases it granted, which the coordinator
// writes to the store in one transaction before any other store operation
// (FarmStore::flush_leases): whatever reads or changes the store sees every lease answered before
// it, and a result is accepted by the store's compare-and-set on its lease exactly as before.
//
// The book is loaded from the store at start-up and per job at the events that change a job's
// leasable units in ways the book cannot follow alone (submit, release, expiry, a failure
// block); it follows the frequent ones itself (a lease, a heartbeat, an accepted result, a
// merge that moves a noise tile's prefix or closes a tile) and drops a job that ends. A lease
// the store no longer accepts when its journal entry is written (the job was cancelled, the
// tile closed, between the book's grant and the store's event) is void: the book forgets it,
// its heartbeat is answered not valid, and its result is dropped as a cancelled unit's.
//
// Which unit a lease gets is the scheduling policy's (server/scheduler.h), which the book keeps
// in step with the store; the book adds the leases themselves (ids, expiry, the worker's held
// leases) and their journal. Each pick is O(log n) in the job's tiles and leases.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "accum/tile_rect.h"
#include "clock.h"
#include "store/job_record.h"
#include "job_store.h"
#include "lease_table.h"
#include "scheduler.h"
#include "store/failures_table.h"
#include "store/sqlite.h"
#include "store/tile_queue.h"
#include "store/tiles_table.h"
#include "store/units_table.h"

namespace tessera::server {

/// A unit leased to a worker, with what it needs to render it.
struct LeasedUnit {
  Lease lease;
  TileRect rect;
  uint32_t sample_begin = 0, sample_end = 0;
  JobOptions options;
  std::string bundle_sha256;
  /// A denoise job's unit over the guides' first samples renders their guides too, of samples
  /// [sample_begin, guide_sample_end); 0: no guides.
  uint32_t guide_sample_end = 0;
  /// Pixel samples the unit renders: the tile's pixels times the batch's samples per pixel.
  uint64_t samples() const { return uint64_t(rect.pixel_count()) * (sample_end - sample_begin); }
};

/// What the book loads of one unfinished job (load_lease_book_job).
struct LeaseBookJob {
  int64_t job_id = 0;
  JobState state = JobState::queued;
  int priority = 0;
  int64_t submitted_unix_ms = 0;
  int64_t started_unix_ms = 0;
  JobSpec spec;
  std::vector<TilePosition> tiles;           ///< every tile, in order
  std::vector<TileQueueRow> queue;           ///< the unborn units of each tile
  std::vector<LiveUnit> units;               ///< rows queued or leased
  std::vector<JobWorkerFailures> failures;   ///< per worker, for blocks
  bool any_build = false;                    ///< JobRecord's
  std::optional<std::string> pinned_build;   ///< JobRecord's
  double verify_rate = 0;                    ///< JobRecord's (server/spot_checks.h)
};

/// Reads what the book keeps of `job_id` from the store (call under the store's lock, after
/// the book's journal was written). nullopt when the job is unknown or final.
std::optional<LeaseBookJob> load_lease_book_job(Database& db, JobStore& jobs, int64_t job_id);

class LeaseBook {
 public:
  using IdSource = std::function<std::string()>;

  LeaseBook(const Clock& clock, int64_t lease_ms, IdSource new_id = random_lease_id);

  int64_t lease_ms() const { return lease_ms_; }
  void set_health_policy(const WorkerHealthPolicy& policy);

  // ---- Workers ----------------------------------------------------------------------------
  /// A worker of renderer build `build` (WorkerRegistration::version): it leases units of jobs
  /// pinned to that build or not pinned yet (Scheduler).
  void add_worker(int64_t worker_id, const std::string& build);
  bool knows_worker(int64_t worker_id);
  /// The worker called at `now_unix_ms` (its last_seen is written with the journal).
  void touch(int64_t worker_id, int64_t now_unix_ms);
  /// The calls recorded by touch() since the last take, worker -> latest time.
  std::map<int64_t, int64_t> take_touches();

  // ---- Jobs -------------------------------------------------------------------------------
  /// Puts (or replaces) the job as the store has it; the journal's leases of the job granted
  /// since the store was read are applied again (or void, when the store's state no longer has
  /// their unit leasable). A final job is dropped.
  void put_job(LeaseBookJob job);
  /// The job ended (cancelled, failed, done, deleted): its units and leases are forgotten.
  void drop_job(int64_t job_id);
  /// Whether the job is in the book (put and not dropped: queued or running).
  bool has_job(int64_t job_id);
  void set_priority(int64_t job_id, int priority);
  /// A merge moved the tile's prefix to `next_batch` (a noise tile's lookahead moves with it);
  /// `closed`: the stopping rule closed the tile (its later units and leases were skipped).
  void tile_merged(int64_t job_id, uint32_t tile, uint32_t next_batch, bool closed);

  // ---- Leases -----------------------------------------------------------------------------
  /// No bound on a call's samples (lease_up_to): only max_units bounds it.
  static constexpr uint64_t kNoSampleBound = UINT64_MAX;
  /// Every lease the worker holds (expiry extended) and new ones up to `max_units`, picked by
  /// the scheduling policy (Scheduler::pick), while the samples of the leases returned add up
  /// to at most `max_samples` (Leasing's lease_sample_budget): the held ones count first, and
  /// the call returns at least one unit when the worker holds one or one is leasable. Empty:
  /// no work. The leases named in `delivering` (results on their way in another call) are
  /// extended but neither returned nor counted.
  std::vector<LeasedUnit> lease_up_to(int64_t worker_id, uint32_t max_units,
                                      const std::vector<std::string>& delivering = {},
                                      uint64_t max_samples = kNoSampleBound);
  /// A heartbeat: the lease's new expiry, nullopt when it is not current for the worker.
  std::optional<int64_t> extend(int64_t worker_id, const std::string& lease_id);
  /// The lease `lease_id` of `worker_id`, when current.
  std::optional<Lease> find(int64_t worker_id, const std::string& lease_id);
  /// The lease ended in the store (its result accepted or dropped): forgotten.
  void ended(const std::string& lease_id);
  /// Its result is held for a spot check (server/spot_checks.h): the lease stays current until
  /// ended() or requeued(), but is never due and never handed back to its worker.
  void hold(const std::string& lease_id);
  /// The unit of the worker's current lease `lease_id`, as leased; nullopt when not current.
  std::optional<LeasedUnit> describe(int64_t worker_id, const std::string& lease_id);
  /// The leases the worker holds (held ones left out).
  std::vector<Lease> leases_of(int64_t worker_id);
  /// The job's spot-check rate; 0 for a job not in the book.
  double verify_rate(int64_t job_id);
  /// Leases whose expiry is before `now_unix_ms`, all written to the store (unit ids known).
  std::vector<Lease> due(int64_t now_unix_ms);
  /// The store requeued the lease's unit (expired or released): the unit is leasable again.
  void requeued(const Lease& lease);
  size_t leases_held();
  /// The leases each worker holds now (workers holding none left out).
  std::map<int64_t, size_t> held_by_worker();
  /// Every lease the store has written -> its unit queued again (the store's revoke_all at
  /// start-up: LeaseTable::revoke_all).
  void revoke_all();

  // ---- The journal ------------------------------------------------------------------------
  /// A lease granted and not yet written to the store.
  struct Grant {
    Lease lease;          ///< unit_id is 0 for an unborn unit until written
    bool unborn = false;  ///< the unit had no row (store/tile_queue.h)
    int64_t at_unix_ms = 0;  ///< when granted (a queued job starts then)
    std::string build;       ///< the worker's renderer build (JobsTable::pin_build)
  };
  /// Takes the journal, oldest first (empty: nothing to write).
  std::vector<Grant> take_journal();
  /// Puts `grants` back before any newer ones (their transaction failed).
  void restore_journal(std::vector<Grant> grants);
  /// The grants were written: `unit_ids[i]` is grants[i]'s unit, or nullopt when the store
  /// refused it (the lease is void and forgotten).
  /// Returns the grants the store took whose lease the book no longer holds (none unless the
  /// book and the store diverged): the caller hands them back to the queue.
  std::vector<Lease> recorded(const std::vector<Grant>& grants,
                              const std::vector<std::optional<int64_t>>& unit_ids);

  /// Counters for tests and BENCHMARKS.md: leases granted, and leases void at their write.
  uint64_t granted();
  uint64_t voided();

 private:
  struct Job {
    JobSpec spec;
    JobPlan plan;
    std::vector<TileRect> rects;
    /// Live leases of the job: (tile, batch) -> lease id.
    std::map<std::pair<uint32_t, uint32_t>, std::string> leased;
    double verify_rate = 0;
  };

  void add_lease(const Lease& lease);
  void remove_lease(const std::string& lease_id);
  LeasedUnit leased_unit(const Job& job, const Lease& lease) const;

  const Clock& clock_;
  int64_t lease_ms_;
  IdSource new_id_;
  std::mutex mu_;  ///< guards everything below (never held while the store is used)
  Scheduler scheduler_;
  std::map<int64_t, std::string> workers_;  ///< id -> renderer build
  std::map<int64_t, int64_t> touches_;
  std::map<int64_t, Job> jobs_;
  std::map<std::string, Lease> leases_;                     ///< by lease id
  std::map<int64_t, std::vector<std::string>> by_worker_;   ///< in grant order
  std::set<std::pair<int64_t, std::string>> by_expiry_;
  std::set<std::string> held_;  ///< leases whose results wait for a spot check (hold())
  std::vector<Grant> journal_;
  uint64_t granted_ = 0, voided_ = 0;
};

/// What write_grants knows and learns of jobs' renderer build pins (JobsTable::pin_build).
struct GrantPins {
  /// Pins read or made by earlier committed writes: a pin never moves and a job id is never
  /// reused, so a job found here costs no statement.
  std::map<int64_t, JobPin> known;
  /// Pins read or made by this write: merge into `known` once its transaction commits.
  std::map<int64_t, JobPin> learned;
  /// Jobs a grant was refused for (a worker of another build than the job's pin).
  std::set<int64_t> refused;
};

/// Writes `grants` (LeaseBook::take_journal) to the store: each unit leased with the grant's
/// id and expiry (LeaseTable::record_grant), each job of a lease written started (queued ->
/// running at its grant's time) and pinned to its first grant's build (JobsTable::pin_build,
/// in this transaction). A grant to a worker of another build than the job's pin is refused
/// (nullopt) and its job put in `pins->refused`: reload it into the book (its unit is still
/// leasable in the store). Without `pins`, every job's pin is read. Call inside a transaction.
/// Returns the unit ids to hand to LeaseBook::recorded.
std::vector<std::optional<int64_t>> write_grants(Database& db, LeaseTable& leases,
                                                 const std::vector<LeaseBook::Grant>& grants,
                                                 GrantPins* pins = nullptr);

/// The book's due leases (expiry is the book's: heartbeats extend leases there) back to the
/// queue, in the store and then in the book. Requires the journal written. Returns how many
/// the store requeued.
int expire_due_leases(LeaseBook& book, LeaseTable& leases, int64_t now_unix_ms);

}  // namespace tessera::server
