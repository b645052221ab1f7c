// The one JSON form of a job (docs/design.md, "The job"): what `tessera status --json`,
// `tessera list --json`, `tessera watch --json` and the dashboard's /api/jobs and /api/jobs/{id}
// write, key for key. The dashboard adds only its live fields (docs/dashboard.md); nothing here
// is renamed on the way.
#pragma once

#include <nlohmann/json.hpp>

#include "tessera/v1/job.pb.h"

namespace tessera::wire {

/// The job as JSON. Keys (docs/dashboard.md, "The job's JSON", lists their meanings):
/// id, state ("queued", "running", "done", "failed", "cancelled"), priority, scene_file,
/// bundle_sha256, options {width, height, spp, max_depth, seed, tile_size, batch_spp, isa,
/// time_budget_s, noise_target}, stop_rule ("spp", "time", "noise"), stop_reason (null while
/// running or failed, else "spp_reached", "noise_target", "max_spp", "time_budget",
/// "cancelled"), progress, spp_merged, reached {spp_min, spp_mean, spp_max, error_max,
/// error_mean, tiles_finished}, counters {units_total, units_done, units_leased, results_merged,
/// results_dropped, leases_expired, units_released, units_skipped, results_wasted, nan_dropped,
/// inf_dropped, samples_merged}, submitted_unix_ms, started_unix_ms, finished_unix_ms,
/// wall_time_s, error ("" unless failed), output_exr, output_png, output_error ("" unless a done
/// job's files could not be written; the paths are empty then), worker_isas, renderer_builds.
nlohmann::json job_json(const v1::JobInfo& job);

/// "queued", "running", ...: the state as the JSON and the CLI write it.
std::string job_state_name(v1::JobState state);

}  // namespace tessera::wire
