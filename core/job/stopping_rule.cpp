#include "job/stopping_rule.h"

#include "accum/film.h"
#include "job/tile_verdict.h"

namespace tessera {

std::string_view to_string(StopRule rule) {
  switch (rule) {
    case StopRule::spp:
      return "spp";
    case StopRule::time:
      return "time";
    case StopRule::noise:
      return "noise";
  }
  return "unknown";
}

std::string_view to_string(StopReason reason) {
  switch (reason) {
    case StopReason::none:
      return "";
    case StopReason::spp_reached:
      return "spp_reached";
    case StopReason::noise_target:
      return "noise_target";
    case StopReason::max_spp:
      return "max_spp";
    case StopReason::time_budget:
      return "time_budget";
    case StopReason::cancelled:
      return "cancelled";
  }
  return "unknown";
}

std::optional<StopRule> stop_rule_from_string(std::string_view name) {
  for (StopRule r : {StopRule::spp, StopRule::time, StopRule::noise}) {
    if (to_string(r) == name) return r;
  }
  return std::nullopt;
}

std::optional<StopReason> stop_reason_from_string(std::string_view name) {
  for (StopReason r : {StopReason::none, StopReason::spp_reached, StopReason::noise_target,
                       StopReason::max_spp, StopReason::time_budget, StopReason::cancelled}) {
    if (to_string(r) == name) return r;
  }
  return std::nullopt;
}

const std::vector<QualityPreset>& quality_presets() {
  static const std::vector<QualityPreset> kPresets = {
      {"draft", StopRule::spp, 16, 0, 0, "16 spp everywhere: composition and lighting checks"},
      {"preview", StopRule::noise, 0, 0.1, 256, "noise 0.1, at most 256 spp: a clean look"},
      {"final", StopRule::noise, 0, 0.02, 4096, "noise 0.02, at most 4096 spp: delivery"},
      {"reference", StopRule::noise, 0, 0.005, 65536,
       "noise 0.005, at most 65536 spp: ground truth for comparisons"},
  };
  return kPresets;
}

std::optional<QualityPreset> find_preset(std::string_view name) {
  for (const QualityPreset& p : quality_presets()) {
    if (p.name == name) return p;
  }
  return std::nullopt;
}

TileVerdict judge_tile(StopRule rule, double noise_target, const Accumulation& merged,
                       uint32_t merged_batches, uint32_t batch_count, uint32_t spp_merged) {
  return judge_tile_given_error(rule, noise_target, estimate_relative_error(merged),
                                merged_batches, batch_count, spp_merged);
}

bool verdict_reads_error(StopRule rule, uint32_t spp_merged) {
  return rule == StopRule::noise && spp_merged >= kNoiseMinSpp;
}

TileVerdict judge_tile_given_error(StopRule rule, double noise_target, double relative_error,
                                   uint32_t merged_batches, uint32_t batch_count,
                                   uint32_t spp_merged) {
  TileVerdict v;
  v.relative_error = relative_error;
  if (verdict_reads_error(rule, spp_merged) && v.relative_error <= noise_target) {
    v.finished = true;
    v.reason = StopReason::noise_target;
  } else if (merged_batches >= batch_count) {
    v.finished = true;
    v.reason = rule == StopRule::spp ? StopReason::spp_reached : StopReason::max_spp;
  }
  return v;
}

}  // namespace tessera
