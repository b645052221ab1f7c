// What `tessera ... --json` prints: jobs and workers as JSON objects for scripts.
#pragma once

#include <nlohmann/json.hpp>

#include "tessera/v1/job.pb.h"
#include "tessera/v1/job_service.pb.h"

namespace tessera::client {

/// {"id", "state" (queued|running|done|failed|cancelled), "progress" (0..1), "priority",
///  "scene_file", "scene_sha256", "options" {...}, "counters" {...}, "spp_merged",
///  "submitted_unix_ms", "started_unix_ms", "finished_unix_ms", "error", "output_exr",
///  "output_png", "worker_isas" [...]}
nlohmann::json to_json(const v1::JobInfo& job);

/// {"id", "name", "threads", "isa", "online", "last_seen_unix_ms", "job_id" (null when idle),
///  "tile", "batch", "units_done", "units_lost"}
nlohmann::json to_json(const v1::WorkerInfo& worker);

}  // namespace tessera::client
