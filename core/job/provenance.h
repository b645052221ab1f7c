// What every image Tessera writes says about how it was made, local or farm: one set of keys,
// "tessera:..." (EXR header attributes, PNG text chunks), listed in docs/design.md
// ("Provenance"). A local render (tessera-worker render) and a farm's job (tessera-server) fill
// the same Provenance; the facts only one of them knows are optional and written only when set.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "job/job_options.h"
#include "job/stopping_rule.h"
#include "job/tile_summary.h"

namespace tessera {

struct Provenance {
  std::string scene_file;  ///< the scene file's name (the farm: its path in the bundle)
  /// The renderer build(s) whose samples the image holds, "; "-separated: more than one means
  /// the image is not one build's bits (docs/design.md, "The determinism contract").
  std::string renderer;
  std::string isa;  ///< Embree's instruction set(s), ","-separated
  const JobOptions* options = nullptr;  ///< the resolved options (required)
  StopReason stop_reason = StopReason::none;
  uint32_t spp = 0;      ///< samples per pixel reached: the minimum over tiles
  TileSummary reached;   ///< spp and estimated relative error over tiles
  uint64_t nan_dropped = 0, inf_dropped = 0;
  std::optional<double> wall_time_s;  ///< the render's (local) or first lease to finish (farm)

  // Known to one side only.
  std::optional<uint64_t> job_id;                   ///< farm
  std::string scene_sha256;                         ///< farm: the bundle's hash
  std::string options_json;                         ///< farm: the resolved options as JSON
  std::optional<uint64_t> samples_merged;           ///< farm
  std::string kernel_isa;                           ///< local: the wavefront kernel's
  std::optional<double> estimated_relative_error;   ///< local: the image's
};

/// The keys and values of `p` (p.options must be set).
std::map<std::string, std::string> provenance_metadata(const Provenance& p);

}  // namespace tessera
