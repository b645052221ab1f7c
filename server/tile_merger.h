// Accepting work-unit results and merging them per tile in batch order (the determinism
// contract's rule 3). Accepting is one transaction: compare-and-set the unit leased -> done on
// its current lease id, then either merge the result (and any waiting successors) into the
// tile's accumulation, or, when earlier batches of the tile are still missing, store it in
// pending_results until they arrive. A tile's accumulation starts at zeros and adds batches
// 0, 1, 2, ... exactly as `tessera-worker render` does, so the pixels are bit-identical.
// After each merged batch the job's stopping rule judges the tile (judge_tile, shared with the
// local renderer); a finished tile merges nothing more: its later units are skipped and results
// that arrived for them (speculative leases, kNoiseLookahead) are counted as wasted. Which
// batches a tile merges is thus a function of the job alone, whatever arrives when.
#pragma once

#include <cstdint>
#include <string>

#include "accum/accumulation.h"
#include "clock.h"
#include "job/stopping_rule.h"
#include "store/sqlite.h"

namespace tessera::server {

struct UnitResult {
  int64_t worker_id = 0;
  std::string lease_id;
  int64_t job_id = 0;
  uint32_t tile = 0;
  uint32_t batch = 0;
  std::string encoded;  ///< encode_accumulation bytes, as uploaded (stored if it must wait)
  std::string isa;      ///< the ISA the worker rendered with
};

struct AcceptOutcome {
  bool accepted = false;      ///< false: dropped (stale or duplicate lease), counted on the job
  std::string reason;         ///< why it was dropped
  uint32_t merged = 0;        ///< results merged by this call (this one and waiting successors)
  uint64_t samples = 0;       ///< pixel samples the accepted result holds (NaN/Inf excluded)
  bool job_complete = false;  ///< no unit of the job is queued or leased: ready to finish
};

class TileMerger {
 public:
  TileMerger(Database& db, const Clock& clock) : db_(db), clock_(clock) {}

  /// Accepts `result` whose decoded accumulation is `decoded` (decoded by the caller, outside
  /// any lock). Throws FarmError: not_found for an unknown unit, invalid_argument when `decoded`
  /// does not cover the unit's tile or holds more samples per pixel than the batch has (the
  /// lease stays current: the worker may retry with a good result).
  AcceptOutcome accept(const UnitResult& result, const Accumulation& decoded);

 private:
  /// The tile met its stopping rule: skip its remaining units, drop its waiting results.
  void close_tile(int64_t job_id, uint32_t tile);

  Database& db_;
  const Clock& clock_;
};

}  // namespace tessera::server
