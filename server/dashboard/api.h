// The dashboard's routes, served by the HTTP front (dashboard/http_server.h); docs/dashboard.md
// lists them:
//   GET  /, /dashboard.css, /dashboard.js, /js/*.js  the page (embedded in the binary)
//   GET  /api/jobs?limit&state&before          a page of jobs, JSON
//   GET  /api/jobs/{id}                        JSON
//   GET  /api/jobs/{id}/preview.png            the merged image so far, sRGB 8-bit
//   GET  /api/jobs/{id}/image.exr              float32 EXR with provenance
//   GET  /api/workers                          JSON
//   POST /api/jobs/{id}/cancel                 token when configured
//   POST /api/jobs/{id}/priority {"priority"}  token when configured
//   GET  /metrics, /healthz, /readyz
// Errors are JSON {"error": "..."} with 400, 401, 403, 404, 409, 411, 413, 415 or 429.
#pragma once

#include <functional>
#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <regex>
#include <string_view>
#include <vector>

#include "dashboard/host_check.h"
#include "dashboard/http_message.h"
#include "dashboard/http_server.h"

namespace tessera::server {

struct JobRecord;
struct WorkerRecord;
struct TileView;
class DashboardApi;

/// The dashboard's routes, answered in two steps so that a request can be refused before its
/// body is read. Both steps are safe to call from several threads at once.
class DashboardRoutes {
 public:
  /// The largest request body read: the API's bodies are a few bytes of JSON.
  static constexpr size_t kMaxBodyBytes = 64 * 1024;

  /// `hosts` judges Host and Origin; `coordinator` and `metrics` must outlive the routes.
  DashboardRoutes(Coordinator& coordinator, const FarmMetrics& metrics, DashboardConfig config,
                  HostCheck hosts);
  ~DashboardRoutes();

  /// Judges a request on its head alone (no body read): Host and Origin (403), the token (401),
  /// then for requests with a body its type (415), a declared length (411, 400) and its size
  /// (413). Returns true when it answered `res`: the body is then never read.
  bool answer_head(const HttpRequest& req, HttpResponse& res) const;
  /// Answers a request that answer_head let through, its body (for methods that carry one)
  /// read into req.body, at most kMaxBodyBytes. Unknown paths and methods get 404.
  void answer(HttpRequest req, HttpResponse& res) const;
  /// The 413 of a body that turned out longer than kMaxBodyBytes while it was read (chunked).
  static void body_too_large(HttpResponse& res);

  /// /healthz and /readyz: answered whatever the limits, the Host or the token.
  static bool is_probe(std::string_view path);
  /// /healthz: its answer reads nothing (it says the process serves HTTP), so the listener may
  /// give it on its I/O thread, never queued behind a handler that waits on the store.
  static bool answers_without_waiting(std::string_view path) { return path == "/healthz"; }
  /// Methods whose requests carry a body the routes read (POST, PUT, PATCH, DELETE).
  static bool carries_body(std::string_view method);

 private:
  struct Route {
    std::string method;  ///< "GET" (HEAD too) or "POST"
    std::regex pattern;  ///< matched against the whole decoded path
    std::function<void(const HttpRequest&, HttpResponse&)> handler;
  };
  std::shared_ptr<DashboardApi> api_;
  std::vector<Route> routes_;
};

/// The JSON of a job in /api/jobs (and, with tiles and provenance added, /api/jobs/{id}).
/// `now_unix_ms` dates elapsed and ETA; `samples_per_s` is the job's recent rate (0: unknown).
nlohmann::json job_json(const JobRecord& job, int64_t now_unix_ms, double samples_per_s);
nlohmann::json tiles_json(const std::vector<TileView>& tiles);

}  // namespace tessera::server
