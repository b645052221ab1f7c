// What `tessera ... --json` prints: jobs and workers as JSON objects for scripts.
#pragma once

#include <nlohmann/json.hpp>

#include "tessera/v1/job.pb.h"
#include "tessera/v1/job_service.pb.h"

namespace tessera::client {

/// {"id", "state" (queued|running|done|failed|cancelled), "progress" (0..1), "priority",
///  "scene_file", "scene_sha256", "options" {...}, "counters" {...}, "spp_merged",
///  "submitted_unix_ms", "started_unix_ms", "finished_unix_ms", "error", "output_exr",
///  "output_png", "worker_isas" [...], "stop_rule" {"rule" (spp|time|noise), "spp",
///  "time_budget_s", "noise_target", "max_spp"}, "stop_reason" (null while running, else
///  spp_reached|noise_target|max_spp|time_budget|cancelled), "wall_time_s", "reached"
///  {"spp_min", "spp_mean", "spp_max", "error_max", "error_mean", "tiles_finished"},
///  "nan_inf_dropped"}
nlohmann::json to_json(const v1::JobInfo& job);

/// "spp 256", "time 10 s (max 4096 spp)", "noise 0.02 (max 4096 spp)".
std::string rule_text(const v1::ResolvedJobOptions& options);
/// "spp_reached", ... ; "" while running.
std::string reason_name(v1::StopReason reason);

/// {"id", "name", "threads", "isa", "online", "last_seen_unix_ms", "job_id" (null when idle),
///  "tile", "batch", "units_done", "units_lost"}
nlohmann::json to_json(const v1::WorkerInfo& worker);

}  // namespace tessera::client
