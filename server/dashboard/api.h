// The dashboard's routes on an httplib::Server (docs/dashboard.md lists them):
//   GET  /, /dashboard.css, /dashboard.js, /js/*.js  the page (embedded in the binary)
//   GET  /api/jobs, /api/jobs/{id}             JSON
//   GET  /api/jobs/{id}/preview.png            the merged image so far, sRGB 8-bit
//   GET  /api/jobs/{id}/image.exr              float32 EXR with provenance
//   GET  /api/workers                          JSON
//   POST /api/jobs/{id}/cancel                 token when configured
//   POST /api/jobs/{id}/priority {"priority"}  token when configured
//   GET  /metrics, /healthz, /readyz
// Errors are JSON {"error": "..."} with 400, 401, 404, 409 or 415.
#pragma once

#include <nlohmann/json_fwd.hpp>

#include "dashboard/http_server.h"

namespace httplib {
class Server;
}

namespace tessera::server {

struct JobRecord;
struct WorkerRecord;
struct TileView;

void install_dashboard_routes(httplib::Server& http, Coordinator& coordinator,
                              const FarmMetrics& metrics, DashboardConfig config);

/// The JSON of a job in /api/jobs (and, with tiles and provenance added, /api/jobs/{id}).
/// `now_unix_ms` dates elapsed and ETA; `samples_per_s` is the job's recent rate (0: unknown).
nlohmann::json job_json(const JobRecord& job, int64_t now_unix_ms, double samples_per_s);
nlohmann::json tiles_json(const std::vector<TileView>& tiles);

}  // namespace tessera::server
