// Accepting work-unit results and merging them per tile in batch order (the determinism
// contract's rule 3). Accepting is one transaction: compare-and-set the unit leased -> done on
// its current lease id, then either merge the result (and any waiting successors) into the
// tile's sum, or, when earlier batches of the tile are still missing, keep it in the results
// table until they arrive. The sum is kept decoded in memory (MergeCache) and stored as a
// checkpoint plus the merged results since, as uploaded (store/results_table.h): a result's
// bytes are written once, when accepted (not at all when its merge is followed by a
// checkpoint), and only every kCheckpointEvery batches (and when the tile finishes) is the
// sum encoded and written. Replaying the checkpoint and the rows in batch order gives the same
// bits, so nothing accepted is lost or merged twice across a crash. A tile's sum starts at
// zeros and adds batches 0, 1, 2, ... exactly as `tessera-worker render` does, so the pixels are
// bit-identical.
// After each merged batch the job's stopping rule judges the tile (judge_tile, shared with the
// local renderer); a finished tile merges nothing more: its later units are skipped and results
// that arrived for them (speculative leases, kNoiseLookahead) are counted as wasted. Which
// batches a tile merges is thus a function of the job alone, whatever arrives when.
#pragma once

#include <compare>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "accum/accumulation.h"
#include "accum/accumulation_codec.h"
#include "clock.h"
#include "job/stopping_rule.h"
#include "merge_cache.h"
#include "store/jobs_table.h"
#include "store/merge_ledger.h"
#include "store/sqlite.h"
#include "store/units_table.h"
#include "waiting_results.h"

namespace tessera::server {

struct UnitResult {
  int64_t worker_id = 0;
  std::string lease_id;
  int64_t job_id = 0;
  uint32_t tile = 0;
  uint32_t batch = 0;
  std::string encoded;  ///< encode_accumulation bytes, as uploaded (stored if it must wait)
  std::string isa;      ///< the ISA the worker rendered with
  uint32_t render_ms = 0;  ///< wall time the worker says it rendered the unit (its rate)
  std::string guides;      ///< encode_guide_tile bytes of a denoise job's unit; empty: none
};

struct AcceptOutcome {
  bool accepted = false;      ///< false: dropped (stale or duplicate lease), counted on the job
  std::string reason;         ///< why it was dropped
  uint32_t merged = 0;        ///< results merged by this call (this one and waiting successors)
  uint64_t samples = 0;       ///< pixel samples the accepted result holds (NaN/Inf excluded)
  bool job_complete = false;  ///< no unit of the job is queued or leased: ready to finish
  /// A merge moved a noise tile's prefix, so units past it may be leasable now (the lookahead
  /// window, store/tile_queue.h): idle workers are woken only then after an upload.
  bool frees_work = false;
  /// When the result merged: its tile's merged prefix after the merge, and whether the
  /// stopping rule closed the tile (the lease book follows both: server/lease_book.h).
  std::optional<uint32_t> tile_next_batch;
  bool tile_closed = false;
};

class TileMerger {
 public:
  /// A tile's sum is written back (checkpointed) after at most this many merged batches.
  static constexpr uint32_t kCheckpointEvery = 8;
  /// How checkpoints are encoded: zstd's fast level. A checkpoint is the server's own (encoded
  /// on its CPU at every checkpoint, decoded when a tile is rebuilt or an image resolved) and
  /// never crosses the network; at level 3 its encode was 5 % of the server's CPU per job
  /// (BENCHMARKS.md, "What a result and a job cost the server, counted").
  static constexpr CodecEffort kCheckpointEffort = CodecEffort::fast;

  /// `cache_bytes` bounds the decoded tiles kept between merges (MergeCache), and a quarter of
  /// it more the decoded results waiting for an earlier batch (WaitingResults).
  TileMerger(Database& db, const Clock& clock,
             size_t cache_bytes = MergeCache::kDefaultBudgetBytes,
             uint32_t checkpoint_every = kCheckpointEvery)
      : db_(db),
        clock_(clock),
        cache_(cache_bytes),
        waiting_(cache_bytes / 4),
        checkpoint_every_(checkpoint_every) {}

  /// Accepts `result` whose decoded accumulation is `decoded` (decoded by the caller, outside
  /// any lock). Throws FarmError: not_found for an unknown unit, invalid_argument when `decoded`
  /// does not cover the unit's tile or holds more samples per pixel than the batch has (the
  /// lease stays current: the worker may retry with a good result).
  AcceptOutcome accept(const UnitResult& result, const Accumulation& decoded);

  /// A result and its decoded accumulation, for accept_all.
  struct Upload {
    const UnitResult* result;
    /// Once the transaction has committed, accept_all moves the sums of a result kept waiting
    /// into WaitingResults (no copy of its decoded tile); its other fields (rect, nan_dropped,
    /// inf_dropped) stay. Untouched when accept_all throws, so the call can be retried.
    Accumulation* decoded;
  };
  /// Accepts several results in one transaction (group commit), each exactly as accept() would
  /// in that order; outcome i answers uploads[i]. All or nothing on errors: a FarmError from one
  /// result rolls back the whole call.
  std::vector<AcceptOutcome> accept_all(const std::vector<Upload>& uploads);
  /// accept_all of several calls' uploads, which may stop between two calls: `ends` are the
  /// calls' ends in `uploads` (increasing, the last one uploads.size()). After each call but the
  /// last, `stop()` is asked; when it says true the transaction commits with the calls so far and
  /// the others are left untouched for the caller to accept in a later transaction. Returns the
  /// outcomes of the uploads accepted: a prefix of `uploads`, whole calls, at least one call.
  /// The coordinator stops when a lease waits for the store (a lease's p99: BENCHMARKS.md,
  /// "Lease latency and capacity").
  std::vector<AcceptOutcome> accept_calls(const std::vector<Upload>& uploads,
                                          const std::vector<size_t>& ends,
                                          const std::function<bool()>& stop);

  /// Writes every tile of the job whose sum is not all in its checkpoint (merged results
  /// appended since its last checkpoint) as its checkpoint, in one transaction. Call before
  /// reading the checkpoints (JobStore::tiles): output, previews, tile maps.
  void checkpoint_job(int64_t job_id);

  /// Drops the job's tiles from memory (it was deleted).
  void forget_job(int64_t job_id) {
    cache_.forget_job(job_id);
    waiting_.forget_job(job_id);
    jobs_seen_.erase(job_id);
    std::erase_if(store_only_, [job_id](const auto& key) { return key.first == job_id; });
    std::erase_if(contributors_,
                  [job_id](const MergeLedger::Contributor& c) { return c.job_id == job_id; });
  }

  const MergeCache& cache() const { return cache_; }
  const WaitingResults& waiting() const { return waiting_; }
  /// Waiting results merged since construction, and how many of them came decoded from memory
  /// (the others were read back from the store and decoded).
  std::pair<uint64_t, uint64_t> waiting_merged() const { return {waiting_merged_, waiting_hits_}; }

 private:
  /// What a transaction in progress merged: tiles that go to the cache once it commits, and
  /// the counters and contributors its results add (written into it before it commits).
  struct Staged {
    std::map<std::pair<int64_t, uint32_t>, MergeCache::Tile> tiles;
    /// Results this transaction stored as waiting, decoded: (job, tile, batch) -> the upload's
    /// accumulation (moved into WaitingResults once the transaction has committed).
    std::map<std::tuple<int64_t, uint32_t, uint32_t>, Accumulation*> waiting;
    MergeLedger ledger;
    /// Tiles whose waiting results this transaction took from waiting_: should it roll back,
    /// their rows are waiting again but not in memory (store_only_).
    std::set<std::pair<int64_t, uint32_t>> taken;
  };
  /// What merging a result and its waiting successors into its tile's sum came to.
  struct MergeRun {
    uint32_t next_batch = 0;  ///< the tile's merged prefix after the merge
    TileVerdict verdict;      ///< the stopping rule's verdict after the last batch merged
    bool error_read = false;  ///< that verdict computed the tile's error
    MergedCounts merged;
  };

  /// accept() inside the caller's transaction; what it merged goes to `staged`.
  AcceptOutcome accept_in_transaction(const UnitResult& result, Accumulation& decoded,
                                      Staged& staged);
  /// The result's unit, with `decoded` checked against it (FarmError as accept()).
  UnitForResult unit_for(const UnitResult& result, const Accumulation& decoded);
  /// Stores the accepted result's guides; FarmError(invalid_argument) when its unit did not ask
  /// for them (a job without denoise, a batch past the guides' samples).
  void store_guides(const UnitResult& result, const UnitForResult& unit);
  /// The result of a lease that is not the unit's current one: counted and dropped.
  AcceptOutcome drop_stale(const UnitResult& result, const UnitForResult& unit);
  /// Merges the result (the tile's next batch) and its waiting successors, and stores the
  /// tile's progress; fills the outcome's merge fields.
  MergedCounts merge(const UnitResult& result, const UnitForResult& unit, Accumulation& decoded,
                     Staged& staged, AcceptOutcome& outcome);
  /// Adds `first` and then every waiting successor to `sum`, strictly in batch order, judging the
  /// tile by the job's stopping rule after each.
  MergeRun merge_in_order(const UnitResult& result, const UnitForResult& unit, Accumulation& sum,
                          const Accumulation& first, Staged& staged);
  /// The waiting result of the tile's `batch`: decoded in memory when this transaction or an
  /// earlier one kept it, else its row read back and decoded into `successor`; nullptr when it
  /// has not arrived.
  const Accumulation* waiting_successor(const UnitResult& result, uint32_t batch, Staged& staged,
                                        Accumulation& successor);
  /// Stores what merge_in_order merged: the error, a checkpoint or the result's row, the tile
  /// closed by its rule, and its merged prefix (compare-and-set on the prefix it started from).
  void store_merge(const UnitResult& result, const UnitForResult& unit, MergeCache::Tile& cached,
                   const MergeRun& run);

  /// The tile's sum of batches [0, next_batch): from `staged` (merged earlier in this
  /// transaction), the cache, else its checkpoint plus its merged results in batch order.
  /// Throws FarmError(internal) when the store's rows do not continue the checkpoint exactly.
  MergeCache::Tile load_sum(int64_t job_id, uint32_t tile, const TileRect& rect,
                            uint32_t next_batch, Staged* staged = nullptr);
  /// Stores `sum` (batches [0, next_batch)) as the tile's checkpoint and deletes the merged
  /// results it covers.
  void write_checkpoint(int64_t job_id, uint32_t tile, const Accumulation& sum,
                        uint32_t next_batch);

  /// The tile met its stopping rule with `next_batch` merged: skip its remaining units, drop
  /// its waiting results.
  void close_tile(int64_t job_id, uint32_t tile, uint32_t next_batch);

  /// Whether a waiting result of (job, tile) may be in the store but not in WaitingResults, so
  /// that a successor missing from memory must be looked for in the results table. False means
  /// it has not arrived: the merge stops without a statement. The first accept of a job in
  /// this process marks every tile of it with rows in `results` (left by an earlier run).
  bool may_wait_in_store(int64_t job_id, uint32_t tile);

  Database& db_;
  const Clock& clock_;
  MergeCache cache_;
  WaitingResults waiting_;
  /// Tiles whose waiting rows may be missing from waiting_: rows from before this process,
  /// entries evicted from waiting_, entries taken from it by a transaction that rolled back.
  std::set<std::pair<int64_t, uint32_t>> store_only_;
  std::set<int64_t> jobs_seen_;  ///< jobs whose earlier rows are in store_only_
  uint64_t waiting_merged_ = 0, waiting_hits_ = 0;
  /// Contributors whose job_contributors row is committed: later results of the same worker
  /// and ISA skip the INSERT OR IGNORE.
  std::set<MergeLedger::Contributor> contributors_;
  uint32_t checkpoint_every_;
  /// Encodes the checkpoints (under the coordinator's store lock, like every call here): one
  /// zstd context for the server, not one per gRPC thread that happens to commit a group.
  AccumulationEncoder checkpoint_encoder_;
};

}  // namespace tessera::server
