#include "proto_convert.h"

#include "wire/job_options_wire.h"

namespace tessera::server {

v1::JobState to_proto(JobState state) {
  switch (state) {
    case JobState::queued: return v1::JOB_STATE_QUEUED;
    case JobState::running: return v1::JOB_STATE_RUNNING;
    case JobState::done: return v1::JOB_STATE_DONE;
    case JobState::failed: return v1::JOB_STATE_FAILED;
    case JobState::cancelled: return v1::JOB_STATE_CANCELLED;
  }
  return v1::JOB_STATE_UNSPECIFIED;
}

std::optional<JobState> from_proto(v1::JobState state) {
  switch (state) {
    case v1::JOB_STATE_QUEUED: return JobState::queued;
    case v1::JOB_STATE_RUNNING: return JobState::running;
    case v1::JOB_STATE_DONE: return JobState::done;
    case v1::JOB_STATE_FAILED: return JobState::failed;
    case v1::JOB_STATE_CANCELLED: return JobState::cancelled;
    default: return std::nullopt;
  }
}

v1::JobInfo to_proto(const JobRecord& job) {
  v1::JobInfo out;
  out.set_id(uint64_t(job.id));
  out.set_state(to_proto(job.state));
  out.set_priority(job.priority);
  out.set_scene_file(job.scene_file);
  out.set_bundle_sha256(job.bundle_sha256);
  *out.mutable_options() = wire::options_to_proto(job.options);
  auto* c = out.mutable_counters();
  c->set_units_total(job.units_total);
  c->set_units_done(job.counters.units_done);
  c->set_units_leased(job.counters.units_leased);
  c->set_results_merged(job.counters.results_merged);
  c->set_results_dropped(job.counters.results_dropped);
  c->set_leases_expired(job.counters.leases_expired);
  c->set_units_released(job.counters.units_released);
  c->set_nan_dropped(job.counters.nan_dropped);
  c->set_inf_dropped(job.counters.inf_dropped);
  c->set_units_skipped(job.counters.units_skipped);
  c->set_results_wasted(job.counters.results_wasted);
  c->set_samples_merged(job.counters.samples_merged);
  out.set_progress(job.progress());
  out.set_spp_merged(job.spp_merged);
  out.set_submitted_unix_ms(job.submitted_unix_ms);
  out.set_started_unix_ms(job.started_unix_ms);
  out.set_finished_unix_ms(job.finished_unix_ms);
  out.set_error(job.error);
  out.set_output_exr(job.output_exr);
  out.set_output_error(job.output_error);
  out.set_output_png(job.output_png);
  for (const std::string& isa : job.isas) out.add_worker_isas(isa);
  for (const std::string& build : job.versions) out.add_renderer_builds(build);
  out.set_stop_reason(wire::stop_reason_to_proto(job.stop_reason));
  out.set_wall_time_s(job.wall_time_s());
  auto* reached = out.mutable_reached();
  reached->set_spp_min(job.reached.spp_min);
  reached->set_spp_mean(job.reached.spp_mean);
  reached->set_spp_max(job.reached.spp_max);
  reached->set_error_max(job.reached.error_max);
  reached->set_error_mean(job.reached.error_mean);
  reached->set_tiles_finished(job.tiles_finished);
  out.set_any_build(job.any_build);
  out.set_pinned_build(job.pinned_build.value_or(""));
  out.set_waiting_for_build(job.waiting_for_build);
  out.set_verify_rate(job.verify_rate);
  out.set_units_checked(job.units_checked);
  out.set_units_unverified(job.units_unverified);
  out.set_denoise(job.denoise);
  out.set_guides(job.guides);
  out.set_output_denoised_exr(job.output_denoised_exr);
  out.set_output_denoised_png(job.output_denoised_png);
  out.set_denoise_error(job.denoise_error);
  return out;
}

v1::WorkerInfo to_proto(const WorkerRecord& w, bool online) {
  v1::WorkerInfo out;
  out.set_id(uint64_t(w.id));
  out.set_name(w.info.name);
  out.set_threads(w.info.threads);
  out.set_isa(w.info.isa);
  out.set_last_seen_unix_ms(w.last_seen_unix_ms);
  out.set_online(online);
  if (w.job_id) {
    out.set_job_id(uint64_t(*w.job_id));
    out.set_tile(w.tile);
    out.set_batch(w.batch);
  }
  out.set_units_done(w.units_done);
  out.set_units_lost(w.units_lost);
  out.set_samples_returned(w.samples_returned);
  out.set_nan_dropped(w.nan_dropped);
  out.set_inf_dropped(w.inf_dropped);
  out.set_health_warning(w.health_warning);
  out.set_units_held(w.units_held);
  out.set_build(w.info.version);
  out.set_state(w.quarantine ? "quarantined" : online ? "online" : "offline");
  if (w.quarantine) {
    v1::WorkerQuarantine* q = out.mutable_quarantine();
    q->set_job_id(uint64_t(w.quarantine->job_id));
    q->set_tile(w.quarantine->tile);
    q->set_batch(w.quarantine->batch);
    q->set_time_unix_ms(w.quarantine->time_unix_ms);
    q->set_reason(w.quarantine->reason);
    for (const int64_t id : w.quarantine->finished_jobs) q->add_finished_jobs(uint64_t(id));
  }
  out.set_checks(w.checks);
  out.set_mismatches(w.mismatches);
  return out;
}

}  // namespace tessera::server
