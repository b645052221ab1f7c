// Spot checks (docs/reliability.md, "Spot checks"): a sampled fraction of a job's units, and the
// first unit of each worker new to the job, is rendered once more by another worker of the same
// renderer build, and the two decoded accumulations are compared bit for bit before the unit's
// result may merge. Determinism makes this exact: one build renders a unit to the same bits on
// any machine (docs/design.md, "The determinism contract").
//
// The first result is held in memory, its unit still leased in the store under its worker's
// lease (held in the lease book: never due, never handed back to its worker), so that merging
// it later is the ordinary compare-and-set on that lease, and the merge stays in batch order: a
// held result waits like one that arrived early. While a worker's first check in a job is open,
// its other results in that job wait with it (its probation). Then:
// - a check result that agrees releases the held result (and the probation's) to merge;
// - one that disagrees leases the unit to a third worker, and so on, until two results agree:
//   that result merges (under the first lease), and every worker whose result differs is
//   quarantined by name: no more work until an operator releases it; its held results are
//   handed back to the queue;
// - when no other eligible worker (same build, online, not quarantined, not among those that
//   rendered it) is there, or none delivered within the bounded wait, the held result merges
//   unchecked and is counted unverified: a farm never hangs on a check.
// A server restart forgets held results (their leases are void like every lease: the units are
// rendered again) but not quarantines (store/quarantine_table.h).
//
// SQL-free and thread-safe (one mutex, never held while calling out except for the callbacks
// given to route(), which may take the lease book's lock).
#pragma once

#include <atomic>
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

#include "accum/accumulation.h"
#include "clock.h"
#include "lease_book.h"
#include "store/quarantine_table.h"
#include "tile_merger.h"

namespace tessera::server {

/// A result held for a check: as uploaded, and decoded.
struct HeldResult {
  UnitResult result;
  Accumulation decoded;
};

/// Counters since the server started (a job's, a worker's, or the farm's).
struct CheckCounts {
  uint64_t checked = 0;     ///< units whose result agreed with another worker's
  uint64_t mismatches = 0;  ///< results that disagreed with the verdict
  uint64_t unverified = 0;  ///< results merged without the check they were due
};

class SpotChecks {
 public:
  using IdSource = std::function<std::string()>;
  /// The bounded wait's default (--check-wait-s): a check not delivered by then merges unchecked.
  static constexpr int64_t kDefaultWaitMs = 60'000;

  SpotChecks(const Clock& clock, int64_t lease_ms, int64_t wait_ms = kDefaultWaitMs,
             IdSource new_id = random_lease_id);

  /// Whether (job, tile, batch) is among the fraction `rate` of the job's units checked: a pure
  /// function of its arguments (a hash of the unit below rate), the same on every server.
  static bool sampled(int64_t job_id, uint32_t tile, uint32_t batch, double rate);
  /// Exact equality of two results: every sum and count bit for bit, and the NaN/Inf counters.
  static bool same_bits(const Accumulation& a, const Accumulation& b);

  void set_wait_ms(int64_t wait_ms);

  // ---- Workers ----------------------------------------------------------------------------
  /// A worker (registered, or first seen since the start) with its name and renderer build.
  void add_worker(int64_t worker_id, const std::string& name, const std::string& build);
  /// The worker called at `now_unix_ms` (lease or heartbeat): online for checks three lease
  /// periods from then.
  void seen(int64_t worker_id, int64_t now_unix_ms);
  /// The quarantines read from the store at start-up.
  void load_quarantines(std::map<std::string, Quarantine> by_name);
  /// Whether the worker's name is quarantined (cheap while no one is).
  bool quarantined(int64_t worker_id);
  std::optional<Quarantine> quarantine_of(int64_t worker_id);
  /// The done jobs with results of the quarantined `worker_name` (Quarantine::finished_jobs).
  void note_finished_jobs(const std::string& worker_name, std::vector<int64_t> jobs);
  /// Ends the quarantine of `worker_name` (in memory); false when it had none.
  bool release(const std::string& worker_name);
  CheckCounts counts_of_worker(int64_t worker_id);
  CheckCounts counts_of_job(int64_t job_id);
  CheckCounts totals();
  size_t quarantined_count();
  /// Held results (checks open plus results waiting on a probation), for tests and /metrics.
  size_t held();

  // ---- Results ----------------------------------------------------------------------------
  /// What to do with one upload call's results, and with results held before.
  struct Routing {
    std::vector<size_t> merge;          ///< the call's results to merge now, in order
    std::vector<HeldResult> released;   ///< results held earlier, decided: merge them too
    /// The call's results not merged now are answered here (accepted: held or a check result;
    /// not: a quarantined worker's); index as in the call, unset for those in `merge`.
    std::map<size_t, AcceptOutcome> answers;
    std::vector<std::string> hold;  ///< lease ids to hold in the lease book (LeaseBook::hold)
    /// Book leases to hand back to the queue: results discarded (their worker quarantined).
    std::vector<std::pair<int64_t, std::string>> requeue;  ///< (worker, lease id)
    /// Workers quarantined by this call, by name (to store, and their leases to hand back).
    std::vector<std::pair<int64_t, std::pair<std::string, Quarantine>>> quarantined;
    bool wake = false;  ///< a check lease is waiting for a worker: wake idle workers
  };
  /// Per result, what the router needs from the rest of the server.
  struct Context {
    /// The job's verify rate (0: no checks; also for a job the server no longer leases).
    std::function<double(int64_t job_id)> rate_of;
    /// The unit of the result's lease as leased (the template of its check leases); nullopt
    /// when the lease is not current.
    std::function<std::optional<LeasedUnit>(const UnitResult&)> unit_of;
  };
  /// Routes one call's results: merged now, held for a check, compared as a check, or dropped
  /// (a quarantined worker's). `decoded[i]` is moved from for the results held.
  Routing route(const std::vector<UnitResult>& results, std::vector<Accumulation>& decoded,
                const Context& context);
  /// Whether route() has anything to do for these results (else merge them all as before):
  /// false when none is of a checked job, a check lease, or a quarantined worker's.
  bool wants(const std::vector<UnitResult>& results,
             const std::function<double(int64_t)>& rate_of);

  // ---- Check leases -----------------------------------------------------------------------
  /// A check the worker may render (same build, not quarantined, not among the unit's workers),
  /// leased to it now; nullopt when none.
  std::optional<LeasedUnit> lease_check(int64_t worker_id);
  /// A check lease's heartbeat: its new expiry, nullopt when it is not the worker's.
  std::optional<int64_t> extend(int64_t worker_id, const std::string& lease_id);
  /// The worker handed the check lease back: another worker may take it. False: not a check.
  bool give_back(int64_t worker_id, const std::string& lease_id);
  /// The bounded wait: checks past it (or with no eligible worker left) release their held
  /// results unchecked; expired check leases may be taken again; checks of jobs `live` says
  /// ended are dropped (their held leases are void with their job).
  Routing sweep(const std::function<bool(int64_t job_id)>& live);

 private:
  using UnitKey = std::tuple<int64_t, uint32_t, uint32_t>;  ///< (job, tile, batch)
  using JobWorker = std::pair<int64_t, int64_t>;             ///< (job, worker)
  struct Candidate {
    int64_t worker_id = 0;
    HeldResult held;
  };
  struct Check {
    LeasedUnit unit;  ///< as first leased: the template of its check leases
    std::string build;
    int64_t since_unix_ms = 0;
    bool probation = false;  ///< its worker's first in the job: that worker's others wait on it
    std::vector<Candidate> results;  ///< [0]: the result held
    std::optional<Lease> lease;      ///< the check lease out now
  };
  struct WorkerState {
    std::string name, build;
    int64_t seen_unix_ms = 0;
    CheckCounts counts;
  };

  /// Routes one result (not a quarantined worker's, not a check): merge now or hold.
  void route_result(size_t i, const UnitResult& r, Accumulation& decoded, const Context& context,
                    Routing& out);
  /// Whether this result (its lease) is held already: an upload retried after a lost answer.
  bool held_already(const UnitResult& r) const;
  /// Opens a check of the held result; false (merge it now, unverified) when no worker could
  /// check it.
  bool open_check(const UnitResult& r, Accumulation& decoded, const LeasedUnit& unit,
                  bool probation, Routing& out);
  /// A check lease's result arrived: judged, and the check decided when two results agree.
  void check_result(const std::string& lease_id, const UnitResult& r, Accumulation& decoded,
                    Routing& out);
  /// Decides the check of `key` if two of its results agree; else asks for another worker.
  void decide(const UnitKey& key, Routing& out);
  /// Releases `held` to merge; unverified counts it as merged without a check.
  void release_held(HeldResult held, bool unverified, Routing& out);
  /// The probation of (job, worker) ended: passed (its waiting results merge), timed out
  /// (they merge unverified) or failed (they go back to the queue).
  enum class ProbationEnd { passed, timed_out, failed };
  void end_probation(const JobWorker& key, ProbationEnd how, Routing& out);
  void quarantine(int64_t worker_id, const UnitKey& unit, const std::string& reason,
                  Routing& out);
  bool online(const WorkerState& w, int64_t now) const;
  /// Whether a worker other than `excluded` could check a unit of `build` now.
  bool eligible_exists(const std::string& build, const std::set<int64_t>& excluded,
                       int64_t now) const;
  static std::set<int64_t> workers_of(const Check& check);
  bool quarantined_locked(int64_t worker_id) const;
  static AcceptOutcome held_outcome(const Accumulation& decoded);

  const Clock& clock_;
  const int64_t lease_ms_;
  IdSource new_id_;
  std::mutex mu_;  ///< guards everything below
  int64_t wait_ms_;
  std::map<int64_t, WorkerState> workers_;
  std::map<std::string, Quarantine> quarantines_;  ///< by worker name
  std::atomic<size_t> quarantined_names_{0};       ///< quarantines_.size(), read without mu_
  std::atomic<size_t> check_leases_out_{0};        ///< check_leases_.size(), read without mu_
  std::atomic<size_t> open_checks_{0};             ///< checks_.size(), read without mu_
  std::map<UnitKey, Check> checks_;
  std::map<std::string, UnitKey> check_leases_;  ///< check lease id -> its unit
  /// Workers new to a job whose first check is open: their other results wait here.
  std::map<JobWorker, std::vector<HeldResult>> probation_;
  std::set<JobWorker> proven_;  ///< passed a check in the job
  std::set<JobWorker> first_unverified_;  ///< its first unit merged unchecked (nobody to check)
  std::map<int64_t, CheckCounts> jobs_;
  CheckCounts totals_;
};

}  // namespace tessera::server
