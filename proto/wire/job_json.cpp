#include "wire/job_json.h"

#include "job/stopping_rule.h"
#include "wire/job_options_wire.h"

namespace tessera::wire {

std::string job_state_name(v1::JobState state) {
  switch (state) {
    case v1::JOB_STATE_QUEUED: return "queued";
    case v1::JOB_STATE_RUNNING: return "running";
    case v1::JOB_STATE_DONE: return "done";
    case v1::JOB_STATE_FAILED: return "failed";
    case v1::JOB_STATE_CANCELLED: return "cancelled";
    default: return "unknown";
  }
}

nlohmann::json job_json(const v1::JobInfo& job) {
  using nlohmann::json;
  const v1::ResolvedJobOptions& o = job.options();
  const v1::JobCounters& c = job.counters();
  const v1::Reached& r = job.reached();
  json isas = json::array();
  for (const std::string& isa : job.worker_isas()) isas.push_back(isa);
  json builds = json::array();
  for (const std::string& build : job.renderer_builds()) builds.push_back(build);
  return json{
      {"id", job.id()},
      {"state", job_state_name(job.state())},
      {"priority", job.priority()},
      {"scene_file", job.scene_file()},
      {"bundle_sha256", job.bundle_sha256()},
      {"options",
       {{"width", o.width()},
        {"height", o.height()},
        {"spp", o.spp()},
        {"max_depth", o.max_depth()},
        // A string: a 64-bit seed is beyond the integers a JSON number holds exactly (2^53).
        {"seed", std::to_string(o.seed())},
        {"tile_size", o.tile_size()},
        {"batch_spp", o.batch_spp()},
        {"batch_schedule", o.batch_schedule().empty() ? "fixed" : o.batch_schedule()},
        {"isa", o.isa()},
        {"time_budget_s", o.time_budget_s()},
        {"noise_target", o.noise_target()}}},
      {"stop_rule", std::string(to_string(stop_rule_from_proto(o.stop_rule())))},
      {"stop_reason", job.stop_reason() == v1::STOP_REASON_UNSPECIFIED
                          ? json(nullptr)
                          : json(std::string(to_string(stop_reason_from_proto(job.stop_reason()))))},
      {"progress", job.progress()},
      {"spp_merged", job.spp_merged()},
      {"reached",
       {{"spp_min", r.spp_min()},
        {"spp_mean", r.spp_mean()},
        {"spp_max", r.spp_max()},
        {"error_max", r.error_max()},
        {"error_mean", r.error_mean()},
        {"tiles_finished", r.tiles_finished()}}},
      {"counters",
       {{"units_total", c.units_total()},
        {"units_done", c.units_done()},
        {"units_leased", c.units_leased()},
        {"results_merged", c.results_merged()},
        {"results_dropped", c.results_dropped()},
        {"leases_expired", c.leases_expired()},
        {"units_released", c.units_released()},
        {"units_skipped", c.units_skipped()},
        {"results_wasted", c.results_wasted()},
        {"nan_dropped", c.nan_dropped()},
        {"inf_dropped", c.inf_dropped()},
        {"samples_merged", c.samples_merged()}}},
      {"submitted_unix_ms", job.submitted_unix_ms()},
      {"started_unix_ms", job.started_unix_ms()},
      {"finished_unix_ms", job.finished_unix_ms()},
      {"wall_time_s", job.wall_time_s()},
      {"error", job.error()},
      {"output_exr", job.output_exr()},
      {"output_png", job.output_png()},
      {"output_error", job.output_error()},
      {"any_build", job.any_build()},
      {"pinned_build", job.pinned_build().empty() ? json(nullptr) : json(job.pinned_build())},
      {"waiting_for_build", job.waiting_for_build()},
      {"verify_rate", job.verify_rate()},
      {"units_checked", job.units_checked()},
      {"units_unverified", job.units_unverified()},
      {"denoise", job.denoise()},
      {"guides", job.guides()},
      {"output_denoised_exr", job.output_denoised_exr()},
      {"output_denoised_png", job.output_denoised_png()},
      {"denoise_error", job.denoise_error()},
      {"worker_isas", isas},
      {"renderer_builds", builds},
  };
}

}  // namespace tessera::wire
