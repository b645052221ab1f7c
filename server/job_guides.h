// A denoise job's guides as the server merges them: per tile, the guides its units uploaded
// (store/guide_results_table.h) over the tile's merged batches, added in batch order exactly as
// `tessera-worker render --guides` adds them (worker/local_render.cpp), so that the farm's
// guides are the local render's bit for bit.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "accum/guide_tile.h"
#include "job/job_plan.h"
#include "store/tiles_table.h"

namespace tessera::server {

/// A tile's stored guides below its merged prefix, (batch, encode_guide_tile bytes) in batch
/// order.
using GuideRows = std::vector<std::pair<uint32_t, std::string>>;

/// The tile's merged guides: `rows` decoded and added in batch order. Every merged batch that
/// began below kGuideSamples must have its row (and no other may be there); a default
/// GuideTile when nothing is merged. Throws std::runtime_error naming the job, tile and batch
/// otherwise, CodecError for bytes that do not decode.
GuideTile merge_tile_guides(int64_t job_id, uint32_t tile, const TilePosition& at,
                            const JobPlan& plan, const GuideRows& rows);

/// Reads one tile's merged guides (JobImages: its rows under the store's lock, merged outside).
using TileGuideReader = std::function<GuideTile(uint32_t tile)>;

}  // namespace tessera::server
