// Re-rendering a quarantined worker's tiles (server/spot_checks.h): results are folded into a
// tile's sum and checkpoints, so a single result cannot be taken back; the tile starts again
// from zero, every unit of it queued (a lease in flight becomes stale: its result is dropped),
// its merged results, waiting results and checkpoint gone, and its job's counters lowered by
// what it had. Every statement of the redo is here.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "store/sqlite.h"

namespace tessera::server {

/// Tiles of queued or running jobs with a unit delivered by a worker named `worker_name`, as
/// (job, tile), in order.
std::vector<std::pair<int64_t, uint32_t>> tiles_delivered_by(Database& db,
                                                             const std::string& worker_name);

/// Starts the tile again from zero (see above). Call inside a transaction. Returns the units
/// queued again.
int64_t redo_tile(Database& db, int64_t job_id, uint32_t tile);

}  // namespace tessera::server
