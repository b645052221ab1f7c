// Stopping rules: the user's trade between speed and accuracy (docs/design.md, "The job"). A job stops
// at a number of samples per pixel (`spp N`), at a wall-time budget (`time T`), or, tile by tile,
// when the estimated relative error of the tile's merged samples reaches a target (`noise E`, up
// to a cap). The decision for one tile is `judge_tile`, shared by the local renderer and the
// farm's merger so that the same job gives the same tiles, and the same bits, on both.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "accum/accumulation.h"

namespace tessera {

enum class StopRule { spp, time, noise };

/// Why a job (or a tile) stopped. `none` while it runs.
enum class StopReason { none, spp_reached, noise_target, max_spp, time_budget, cancelled };

std::string_view to_string(StopRule rule);
std::string_view to_string(StopReason reason);
std::optional<StopRule> stop_rule_from_string(std::string_view name);
std::optional<StopReason> stop_reason_from_string(std::string_view name);

/// The default cap of `noise` and `time` jobs, in samples per pixel.
inline constexpr uint32_t kDefaultMaxSpp = 4096;
/// A tile's error is first judged once it has this many samples per pixel.
inline constexpr uint32_t kNoiseMinSpp = 16;
/// The default batch of a `noise` job: one check per batch, the first at kNoiseMinSpp.
inline constexpr uint32_t kNoiseBatchSpp = 16;

/// A named quality preset: plain stopping rule values (docs/accuracy.md has the table).
struct QualityPreset {
  std::string_view name;
  StopRule rule;
  uint32_t spp;          ///< spp rule: samples per pixel; others: 0
  double noise;          ///< noise rule: the target; others: 0
  uint32_t max_spp;      ///< noise rule: the cap; others: 0
  std::string_view use;  ///< one line for the help text
};

/// Every preset, in the order the help lists them.
const std::vector<QualityPreset>& quality_presets();
/// The preset called `name`, or nullopt.
std::optional<QualityPreset> find_preset(std::string_view name);

/// What the rule decided for a tile after a merge.
struct TileVerdict {
  bool finished = false;                 ///< no more batches for this tile
  StopReason reason = StopReason::none;  ///< why, when finished
  double relative_error = 0;             ///< estimate_relative_error of the merged tile
};

/// The rule's decision for one tile whose merged accumulation `merged` holds batches
/// [0, merged_batches) of `batch_count`, i.e. `spp_merged` samples per pixel. A tile is finished
/// when every batch is merged (spp_reached for `spp`, max_spp for `noise` and `time`); a `noise`
/// tile also when spp_merged >= kNoiseMinSpp and its error <= `noise_target` (noise_target,
/// preferred to max_spp when both hold). The time budget is the scheduler's business, not a
/// tile's. Pure: depends on the merged data and the rule only (determinism contract rule 4).
TileVerdict judge_tile(StopRule rule, double noise_target, const Accumulation& merged,
                       uint32_t merged_batches, uint32_t batch_count, uint32_t spp_merged);

}  // namespace tessera
