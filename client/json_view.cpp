#include "json_view.h"

#include "job_client.h"

namespace tessera::client {

nlohmann::json to_json(const v1::JobInfo& job) {
  const auto& o = job.options();
  const auto& c = job.counters();
  nlohmann::json isas = nlohmann::json::array();
  for (const std::string& isa : job.worker_isas()) isas.push_back(isa);
  return {
      {"id", job.id()},
      {"state", state_name(job.state())},
      {"progress", job.progress()},
      {"priority", job.priority()},
      {"scene_file", job.scene_file()},
      {"scene_sha256", job.bundle_sha256()},
      {"options",
       {{"width", o.width()},
        {"height", o.height()},
        {"spp", o.spp()},
        {"max_depth", o.max_depth()},
        {"seed", o.seed()},
        {"tile_size", o.tile_size()},
        {"batch_spp", o.batch_spp()},
        {"isa", o.isa()}}},
      {"counters",
       {{"units_total", c.units_total()},
        {"units_done", c.units_done()},
        {"units_leased", c.units_leased()},
        {"results_merged", c.results_merged()},
        {"results_dropped", c.results_dropped()},
        {"leases_expired", c.leases_expired()},
        {"units_released", c.units_released()},
        {"nan_dropped", c.nan_dropped()},
        {"inf_dropped", c.inf_dropped()}}},
      {"spp_merged", job.spp_merged()},
      {"submitted_unix_ms", job.submitted_unix_ms()},
      {"started_unix_ms", job.started_unix_ms()},
      {"finished_unix_ms", job.finished_unix_ms()},
      {"error", job.error()},
      {"output_exr", job.output_exr()},
      {"output_png", job.output_png()},
      {"worker_isas", isas},
  };
}

nlohmann::json to_json(const v1::WorkerInfo& w) {
  return {
      {"id", w.id()},
      {"name", w.name()},
      {"threads", w.threads()},
      {"isa", w.isa()},
      {"online", w.online()},
      {"last_seen_unix_ms", w.last_seen_unix_ms()},
      {"job_id", w.job_id() == 0 ? nlohmann::json(nullptr) : nlohmann::json(w.job_id())},
      {"tile", w.tile()},
      {"batch", w.batch()},
      {"units_done", w.units_done()},
      {"units_lost", w.units_lost()},
      {"samples_returned", w.samples_returned()},
      {"nan_dropped", w.nan_dropped()},
      {"inf_dropped", w.inf_dropped()},
      {"health_warning", w.health_warning()},
  };
}

}  // namespace tessera::client
