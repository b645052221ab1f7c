// What `tessera ... --json` prints: jobs and workers as JSON objects for scripts.
#pragma once

#include <nlohmann/json.hpp>

#include "tessera/v1/job.pb.h"
#include "tessera/v1/job_service.pb.h"

namespace tessera::client {

/// The one JSON form of a job, shared with the dashboard's API (wire/job_json.h).
nlohmann::json to_json(const v1::JobInfo& job);

/// "spp 256", "time 10 s (max 4096 spp)", "noise 0.02 (max 4096 spp)".
std::string rule_text(const v1::ResolvedJobOptions& options);
/// "spp_reached", ... ; "" while running.
std::string reason_name(v1::StopReason reason);

/// {"id", "name", "threads", "isa", "online", "last_seen_unix_ms", "job_id" (null when idle),
///  "tile", "batch", "units_done", "units_lost"}
nlohmann::json to_json(const v1::WorkerInfo& worker);

}  // namespace tessera::client
