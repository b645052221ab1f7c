// The scheduling policy: which unit a worker leases next. SQL-free and in memory; the lease book
// (server/lease_book.h) keeps one and the server leases through it, so this file is the one
// home of the rules (docs/farm.md, "Scheduling"):
// - jobs by priority (higher first), then age (older first), then id;
// - a worker blocked from a job (WorkerHealthPolicy: failures_to_block failures there, the last
//   within forgive_ms) gets none of its units;
// - within a job, its first leasable unit in (batch, tile) order, a unit back from a lease (with
//   its row) or one not created yet (store/tile_queue.h) alike: a job's tiles progress together
//   (a preview that sharpens evenly) and batch b+1 is leased once no batch <= b is left unleased,
//   without waiting for results (no barrier);
// - a `time` job past its budget (started + budget <= now) gets what is left of batch 0 only:
//   every tile gets its first batch, nothing else starts;
// - a `noise` tile is leased at most kNoiseLookahead batches past its merged prefix
//   (speculation the rule may waste, never a change of bits: see tile_merger.h);
// - a job is leased only to workers of its pinned renderer build; a job not pinned yet is pinned
//   to the build of the worker its first unit goes to (unless it is any_build), so that no two
//   builds render units of one job (docs/design.md, "The determinism contract");
// - one call's units may be bounded by their samples (SampleBound, the lease's budget: see
//   leasing.h): the picks stop at the first unit that would go over it, so a call never skips
//   a large unit for smaller ones of a later job.
// Each pick is O(log n) in the job's tiles and units back in the queue. Not thread-safe: the
// book calls it under its own mutex.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace tessera::server {

class Scheduler {
 public:
  /// A noise tile with batches [0, next_batch) merged is leased batches < next_batch + this.
  static constexpr uint32_t kNoiseLookahead = 2;

  /// A tile's units: batches [next_lease, lease_end) have no row yet (TileQueueRow), and
  /// batches [0, next_batch) are merged (its prefix).
  struct Tile {
    uint32_t next_lease = 0, lease_end = 0, next_batch = 0;
  };
  /// A unit back in the queue, with its row.
  struct Requeued {
    uint32_t batch = 0, tile = 0;
    int64_t unit_id = 0;
    auto operator<=>(const Requeued&) const = default;
  };
  /// What the policy needs of a queued or running job.
  struct Job {
    int64_t id = 0;
    int priority = 0;
    int64_t submitted_unix_ms = 0;
    /// 0 while the job is queued; its first pick starts it (queued -> running).
    int64_t started_unix_ms = 0;
    bool running = false;
    bool noise = false;          ///< StopRule::noise: the lookahead applies
    int64_t time_budget_ms = 0;  ///< > 0 for a StopRule::time job
    std::vector<Tile> tiles;
    std::vector<Requeued> requeued;
    /// Failures per worker: (count, last failure time).
    std::map<int64_t, std::pair<int64_t, int64_t>> failures;
    bool any_build = false;            ///< leased to workers of every build
    std::optional<std::string> build;  ///< the build it is pinned to; nullopt: not yet
  };
  /// A unit picked for a worker: unit_id 0 and `unborn` when it has no row yet.
  struct Pick {
    int64_t job_id = 0;
    uint32_t tile = 0, batch = 0;
    int64_t unit_id = 0;
    bool unborn = false;
    bool operator==(const Pick&) const = default;
  };

  /// A bound on the samples of one pick()'s units: they add up to at most `max_samples`, except
  /// that the first unit is picked whatever its samples when `first_free` (a call always
  /// leases something when there is work). Without `samples_of`, no bound.
  struct SampleBound {
    std::function<uint64_t(const Pick&)> samples_of;
    uint64_t max_samples = 0;
    bool first_free = true;
  };

  /// WorkerHealthPolicy's blocking half (server/lease_table.h).
  void set_block_policy(int failures_to_block, int64_t forgive_ms);

  /// The worker's renderer build (a worker never set is of build "").
  void set_worker_build(int64_t worker_id, const std::string& build);

  /// Puts (or replaces) a job. A job that is neither queued nor running is not put: drop it.
  void put_job(const Job& job);
  void drop_job(int64_t job_id);
  void set_priority(int64_t job_id, int priority);
  /// A merge moved the tile's prefix to `next_batch` (a noise tile's lookahead moves with it);
  /// `closed`: the stopping rule closed the tile, none of its units is leased any more.
  void tile_merged(int64_t job_id, uint32_t tile, uint32_t next_batch, bool closed);
  /// A leased unit came back to the queue (its lease expired or was released).
  void requeued(int64_t job_id, const Requeued& unit);

  /// Up to `n` units for `worker_id` at `now_unix_ms`, within `bound`, taken (never picked
  /// again unless requeued), in the order above; the job of the first starts at `now_unix_ms`
  /// if queued.
  std::vector<Pick> pick(int64_t worker_id, int64_t now_unix_ms, size_t n,
                         const SampleBound& bound);
  /// pick() with no bound on the samples.
  std::vector<Pick> pick(int64_t worker_id, int64_t now_unix_ms, size_t n);
  /// Takes the given unit, picked earlier for a worker of `build` (the book applies its unwritten
  /// grants again after a job was put again): false when the job no longer has it leasable or
  /// is pinned to another build.
  bool take(const Pick& unit, int64_t at_unix_ms, const std::string& build = "");

  /// The build the job is pinned to (nullopt: not yet, any_build, or unknown).
  std::optional<std::string> pinned_build(int64_t job_id) const;
  /// For tests: the job's start time as the policy sees it (0: queued or unknown).
  int64_t started_unix_ms(int64_t job_id) const;

 private:
  struct State {
    Job job;
    /// (next_lease, tile) of every tile whose next unborn unit is leasable (below lease_end
    /// and, for a noise job, within the lookahead of its merged prefix).
    std::set<std::pair<uint32_t, uint32_t>> open;
    std::set<Requeued> requeued;
  };
  /// (-priority, submitted, id); the priority negated in 64 bits, where INT_MIN's negation fits.
  using OrderKey = std::tuple<int64_t, int64_t, int64_t>;
  static OrderKey order_key(const Job& j);

  bool eligible(const State& s, uint32_t tile) const;
  /// Removes tile's entry from s.open; call before changing the tile, then reopen().
  void unopen(State& s, uint32_t tile);
  void reopen(State& s, uint32_t tile);
  /// Leases the tile's next unborn unit: moves its next_lease on, keeping s.open in step.
  void lease_unborn(State& s, uint32_t tile);
  bool blocked(const State& s, int64_t worker_id, int64_t now) const;
  /// Whether a worker of `build` may lease the job's units (pinned to it, not pinned, any).
  static bool admits(const State& s, const std::string& build);
  /// The job's first unit went to a worker of `build`: pinned to it unless any_build.
  static void pin(State& s, const std::string& build);
  /// The job's first leasable unit (not taken), or false.
  bool next_unit(const State& s, int64_t now, Pick& out) const;
  /// Takes `unit`, which next_unit() just gave.
  void take_next(State& s, const Pick& unit, int64_t now);
  static void start(State& s, int64_t at);

  int failures_to_block_ = 2;
  int64_t forgive_ms_ = 600'000;
  std::map<int64_t, State> jobs_;
  std::map<int64_t, std::string> worker_builds_;
  std::set<OrderKey> order_;
};

}  // namespace tessera::server
