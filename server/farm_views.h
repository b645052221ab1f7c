// What the dashboard shows that the job records do not hold: a job's tiles with what each has
// merged and its error estimate, and farm-wide totals for /metrics. Read from the store, the
// tiles decoded outside its lock.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "farm_store.h"
#include "result_intake.h"

namespace tessera::server {

/// A tile of a job as the dashboard shows it (FarmViews::tile_map).
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

/// Farm-wide totals from the store (FarmViews::totals), for /metrics.
struct FarmTotals {
  std::map<std::string, uint64_t> jobs_by_state;  ///< every state name, 0 when none
  uint64_t units_leased_now = 0;
  uint64_t units_done = 0;        ///< over all jobs, as stored
  uint64_t leases_expired = 0;
  uint64_t results_dropped = 0;
  uint64_t samples_merged = 0;
  uint64_t workers = 0;
};

class FarmViews {
 public:
  FarmViews(FarmStore& store, ResultIntake& intake) : store_(store), intake_(intake) {}

  /// Every tile of the job with what is merged and the error estimates. Throws
  /// FarmError(not_found).
  TileMap tile_map(int64_t job_id);
  /// Farm-wide totals in one read of the store.
  FarmTotals totals();

 private:
  FarmStore& store_;
  ResultIntake& intake_;
};

}  // namespace tessera::server
