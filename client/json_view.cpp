#include "json_view.h"

#include <cstdio>

#include "job/stopping_rule.h"
#include "job_client.h"
#include "wire/job_options_wire.h"

namespace tessera::client {

std::string rule_text(const v1::ResolvedJobOptions& o) {
  char buf[128];
  switch (o.stop_rule()) {
    case v1::STOP_RULE_TIME:
      std::snprintf(buf, sizeof buf, "time %g s (max %u spp)", o.time_budget_s(), o.spp());
      return buf;
    case v1::STOP_RULE_NOISE:
      std::snprintf(buf, sizeof buf, "noise %g (max %u spp)", o.noise_target(), o.spp());
      return buf;
    default: return "spp " + std::to_string(o.spp());
  }
}

std::string reason_name(v1::StopReason reason) {
  return std::string(to_string(wire::stop_reason_from_proto(reason)));
}

namespace {

nlohmann::json rule_json(const v1::ResolvedJobOptions& o) {
  const StopRule rule = wire::stop_rule_from_proto(o.stop_rule());
  nlohmann::json j = {{"rule", std::string(to_string(rule))}};
  if (rule == StopRule::spp) j["spp"] = o.spp();
  if (rule == StopRule::time) j["time_budget_s"] = o.time_budget_s();
  if (rule == StopRule::noise) j["noise_target"] = o.noise_target();
  if (rule != StopRule::spp) j["max_spp"] = o.spp();
  return j;
}

}  // namespace

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
        {"inf_dropped", c.inf_dropped()},
        {"units_skipped", c.units_skipped()},
        {"results_wasted", c.results_wasted()},
        {"samples_merged", c.samples_merged()}}},
      {"spp_merged", job.spp_merged()},
      {"submitted_unix_ms", job.submitted_unix_ms()},
      {"started_unix_ms", job.started_unix_ms()},
      {"finished_unix_ms", job.finished_unix_ms()},
      {"error", job.error()},
      {"output_exr", job.output_exr()},
      {"output_png", job.output_png()},
      {"worker_isas", isas},
      {"stop_rule", rule_json(o)},
      {"stop_reason", job.stop_reason() == v1::STOP_REASON_UNSPECIFIED
                          ? nlohmann::json(nullptr)
                          : nlohmann::json(reason_name(job.stop_reason()))},
      {"wall_time_s", job.wall_time_s()},
      {"reached",
       {{"spp_min", job.reached().spp_min()},
        {"spp_mean", job.reached().spp_mean()},
        {"spp_max", job.reached().spp_max()},
        {"error_max", job.reached().error_max()},
        {"error_mean", job.reached().error_mean()},
        {"tiles_finished", job.reached().tiles_finished()}}},
      {"nan_inf_dropped", c.nan_dropped() + c.inf_dropped()},
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
