// The stopping rule's tile decision in two parts (core/job/stopping_rule.h, judge_tile, is the
// whole): whether the decision reads the tile's error, and the decision given that error. The
// farm's merger uses them to compute the error only where it is read or stored
// (server/tile_merger.cpp); judge_tile is defined through them, so both decide alike.
#pragma once

#include <cstdint>

#include "job/stopping_rule.h"

namespace tessera {

/// Whether judge_tile's decision reads the tile's error: a `noise` tile from kNoiseMinSpp on.
/// Otherwise the decision depends on the batch count alone and the error need not be computed.
bool verdict_reads_error(StopRule rule, uint32_t spp_merged);

/// judge_tile with the tile's error given (estimate_relative_error of the merged tile; any value
/// when !verdict_reads_error(rule, spp_merged)); the verdict's relative_error is that value.
TileVerdict judge_tile_given_error(StopRule rule, double noise_target, double relative_error,
                                   uint32_t merged_batches, uint32_t batch_count,
                                   uint32_t spp_merged);

}  // namespace tessera
