#include "job/provenance.h"

#include <stdexcept>

#include "job/batch_schedule.h"

namespace tessera {

std::map<std::string, std::string> provenance_metadata(const Provenance& p) {
  if (!p.options) throw std::invalid_argument("provenance_metadata: no job options");
  const JobOptions& o = *p.options;
  std::map<std::string, std::string> m;
  m["tessera:scene_file"] = p.scene_file;
  m["tessera:renderer_version"] = p.renderer;
  m["tessera:isa"] = p.isa;
  m["tessera:max_depth"] = std::to_string(o.max_depth);
  m["tessera:seed"] = std::to_string(o.seed);
  m["tessera:tile"] = std::to_string(o.tile_size);
  // The cap of a progressive schedule (docs/farm.md, "Batches").
  m["tessera:batch"] = std::to_string(o.batch_spp);
  m["tessera:batch_schedule"] = std::string(to_string(o.batch_kind));
  m["tessera:stop_rule"] = std::string(to_string(o.rule));
  m["tessera:stop_reason"] = std::string(to_string(p.stop_reason));
  if (o.rule == StopRule::noise) {
    m["tessera:noise_target"] = std::to_string(o.noise_target);
    m["tessera:max_spp"] = std::to_string(o.spp);
  } else if (o.rule == StopRule::time) {
    m["tessera:time_budget_s"] = std::to_string(o.time_budget_s);
    m["tessera:max_spp"] = std::to_string(o.spp);
  }
  m["tessera:spp"] = std::to_string(p.spp);
  m["tessera:spp_min"] = std::to_string(p.reached.spp_min);
  m["tessera:spp_mean"] = std::to_string(p.reached.spp_mean);
  m["tessera:spp_max"] = std::to_string(p.reached.spp_max);
  m["tessera:tile_error_max"] = std::to_string(p.reached.error_max);
  m["tessera:tile_error_mean"] = std::to_string(p.reached.error_mean);
  m["tessera:nan_dropped"] = std::to_string(p.nan_dropped);
  m["tessera:inf_dropped"] = std::to_string(p.inf_dropped);
  if (p.wall_time_s) m["tessera:wall_time_s"] = std::to_string(*p.wall_time_s);
  if (p.job_id) m["tessera:job_id"] = std::to_string(*p.job_id);
  if (!p.scene_sha256.empty()) m["tessera:scene_sha256"] = p.scene_sha256;
  if (!p.options_json.empty()) m["tessera:job_options"] = p.options_json;
  if (p.samples_merged) m["tessera:samples_merged"] = std::to_string(*p.samples_merged);
  if (!p.kernel_isa.empty()) m["tessera:kernel_isa"] = p.kernel_isa;
  if (p.estimated_relative_error) {
    m["tessera:estimated_relative_error"] = std::to_string(*p.estimated_relative_error);
  }
  return m;
}

}  // namespace tessera
