#include "dashboard/api.h"

#include <openssl/crypto.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <climits>
#include <map>
#include <memory>
#include <mutex>
#include <string_view>
#include <nlohmann/json.hpp>

#include "coordinator.h"
#include "dashboard/farm_metrics.h"
#include "dashboard/prometheus_text.h"
#include "dashboard/store_status.h"
#include "dashboard_assets.h"
#include "farm_error.h"
#include "job_output.h"
#include "proto_convert.h"
#include "scene/message_text.h"
#include "wire/job_json.h"
#include "wire/job_options_wire.h"

namespace tessera::server {

using nlohmann::json;

namespace {

constexpr size_t kMaxBodyBytes = DashboardRoutes::kMaxBodyBytes;

json optional_number(std::optional<double> v) { return v ? json(*v) : json(nullptr); }

uint64_t samples_total(const JobRecord& job) {
  return uint64_t(job.options.width) * uint64_t(job.options.height) * job.options.spp;
}

void send_json(HttpResponse& res, int status, const json& body) {
  res.status = status;
  res.set_header("Cache-Control", "no-store");
  res.set_content(body.dump(), "application/json");
}

void send_error(HttpResponse& res, int status, const std::string& message) {
  set_json_error(res, status, message);
}

int status_of(ErrorCode code) {
  switch (code) {
    case ErrorCode::invalid_argument: return 400;
    case ErrorCode::not_found: return 404;
    case ErrorCode::failed_precondition: return 409;
    case ErrorCode::resource_exhausted: return 429;
    case ErrorCode::internal: return 500;
  }
  return 500;
}

/// The {id} of a route: digits only (the route's regex), 1..INT64_MAX. Throws FarmError.
int64_t job_id_of(const HttpRequest& req) {
  const std::string& text = req.matches.at(1);
  if (text.size() > 18 || std::stoll(text) < 1) {
    throw FarmError(ErrorCode::not_found, "no job " + text);
  }
  return std::stoll(text);
}

/// The query parameter `name` as a whole number in [1, max]; `fallback` when absent. Throws
/// FarmError(invalid_argument) naming the parameter.
int64_t number_param(const HttpRequest& req, std::string_view name, int64_t max, int64_t fallback) {
  if (!req.has_param(name)) return fallback;
  const std::string text = req.param(name);
  const bool digits = !text.empty() && text.size() <= 18 &&
                      text.find_first_not_of("0123456789") == std::string::npos;
  if (!digits || std::stoll(text) < 1 || std::stoll(text) > max) {
    throw FarmError(ErrorCode::invalid_argument, std::string(name) + " must be 1.." +
                                                     std::to_string(max) + " (got \"" +
                                                     printable(text) + "\")");
  }
  return std::stoll(text);
}

/// The listing /api/jobs?limit=N&state=S[,S...]&before=ID asks for (docs/dashboard.md); `state`
/// may also be repeated. Throws FarmError(invalid_argument) naming the parameter.
JobQuery job_query(const HttpRequest& req) {
  JobQuery query;
  query.limit = uint32_t(number_param(req, "limit", kMaxJobPage, kMaxJobPage));
  query.before_id = number_param(req, "before", INT64_MAX, 0);
  for (const auto& [param, text] : req.params) {
    if (param != "state") continue;
    for (size_t begin = 0; begin <= text.size();) {
      const size_t end = std::min(text.find(',', begin), text.size());
      const std::string name = text.substr(begin, end - begin);
      const std::optional<JobState> state = job_state_from_string(name);
      if (!state) {
        throw FarmError(ErrorCode::invalid_argument,
                        "state must be queued, running, done, failed or cancelled, or several "
                        "with commas (got \"" + printable(name) + "\")");
      }
      query.states.push_back(*state);
      begin = end + 1;
    }
  }
  return query;
}

}  // namespace

/// Everything the routes share; owned by the routes and their handlers' closures.
class DashboardApi {
 public:
  DashboardApi(Coordinator& coordinator, const FarmMetrics& metrics, DashboardConfig config,
               HostCheck hosts)
      : coordinator_(coordinator),
        metrics_(metrics),
        config_(std::move(config)),
        hosts_(std::move(hosts)) {}

  /// Runs a handler, mapping FarmError and other exceptions to JSON errors.
  template <typename F>
  void guarded(HttpResponse& res, F&& handler) {
    try {
      handler();
    } catch (const FarmError& e) {
      send_error(res, status_of(e.code()), e.what());
    } catch (const std::exception& e) {
      send_error(res, 500, e.what());
    }
  }

  /// True when the request carries the token (or the server has none); otherwise answers 401
  /// and returns false. Called before anything of the request's body is read.
  bool authorised(const HttpRequest& req, HttpResponse& res) const {
    if (config_.token.empty()) return true;
    const std::string expected = "Bearer " + config_.token;
    const std::string given = req.header("Authorization");
    // Constant-time comparison: the time taken never tells how much of the token matched.
    if (given.size() != expected.size() ||
        CRYPTO_memcmp(given.data(), expected.data(), expected.size()) != 0) {
      res.set_header("WWW-Authenticate", "Bearer");
      send_error(res, 401,
                 given.empty() ? "this server needs a token: send Authorization: Bearer TOKEN"
                               : "wrong token");
      return false;
    }
    return true;
  }

  json job_summary(const JobRecord& job, int64_t now) {
    json j = job_json(job, now, job_rate(job));
    j["relative_error"] = optional_number(job_error(job));
    return j;
  }

  json jobs(const JobQuery& query) {
    const int64_t now = coordinator_.clock().now_unix_ms();
    const JobPage page = coordinator_.jobs(query);
    json list = json::array();
    for (const JobRecord& job : page.jobs) list.push_back(job_summary(job, now));
    return json{{"jobs", list},
                {"total", page.total},
                {"next_before",
                 page.next_before_id > 0 ? json(page.next_before_id) : json(nullptr)},
                {"server_time_unix_ms", now},
                {"token_required", !config_.token.empty()},
                {"samples_per_s", metrics_.farm_samples_per_s()},
                // The page polls this list: every page shows the store's banner from it.
                {"store", store_json(store_status(coordinator_))}};
  }

  json job_detail(int64_t id) {
    const JobRecord job = coordinator_.job(id);
    const std::shared_ptr<const TileMap> map = tile_map(job);
    json j = job_summary(job, coordinator_.clock().now_unix_ms());
    j["tiles"] = tiles_json(map->tiles);
    j["provenance"] = JobOutput::provenance(job);
    j["token_required"] = !config_.token.empty();
    return j;
  }

  /// A quarantined worker's {job, tile, batch, time_unix_ms, reason}; null when not.
  static json quarantine_json(const std::optional<Quarantine>& q) {
    if (!q) return nullptr;
    return json{{"job", q->job_id}, {"tile", q->tile}, {"batch", q->batch},
                {"time_unix_ms", q->time_unix_ms}, {"reason", q->reason},
                {"finished_jobs", q->finished_jobs}};
  }

  json workers() {
    json list = json::array();
    const int64_t now = coordinator_.clock().now_unix_ms();
    for (const WorkerRecord& w : coordinator_.workers()) {
      const bool online = coordinator_.online(w);
      json unit = nullptr;
      if (w.job_id) unit = json{{"job_id", *w.job_id}, {"tile", w.tile}, {"batch", w.batch}};
      list.push_back(json{
          {"id", w.id},
          {"name", w.info.name},
          {"threads", w.info.threads},
          {"isa", w.info.isa},
          {"version", w.info.version},
          {"state", w.quarantine ? "quarantined"
                    : !online    ? "offline"
                    : w.job_id   ? "busy"
                                 : "idle"},
          {"quarantine", quarantine_json(w.quarantine)},
          {"checks", w.checks},
          {"mismatches", w.mismatches},
          {"online", online},
          {"unit", unit},
          {"units_held", w.units_held},
          {"samples_per_s", metrics_.worker_samples_per_s(w.id)},
          {"registered_unix_ms", w.registered_unix_ms},
          {"last_seen_unix_ms", w.last_seen_unix_ms},
          {"last_seen_s", double(now - w.last_seen_unix_ms) / 1000.0},
          {"units_done", w.units_done},
          {"failures", w.units_lost},
      });
    }
    return json{{"workers", list}, {"server_time_unix_ms", now}};
  }

  std::string metrics_text() {
    FarmSnapshotForMetrics s;
    s.store = store_status(coordinator_);
    try {
      s.totals = coordinator_.totals();
      for (const WorkerRecord& w : coordinator_.workers()) s.workers_online += coordinator_.online(w);
      s.checks = coordinator_.check_totals();
      s.workers_quarantined = coordinator_.quarantined_workers();
    } catch (const SqliteError&) {
      // A damaged store may not answer the totals' queries: the store's gauges (which need no
      // query) must still say so, so /metrics leaves out only the families read from it.
      if (!s.store.damaged()) throw;
      s.store_readable = false;
    }
    const FarmMetrics& m = metrics_;
    s.samples_per_s = m.farm_samples_per_s();
    s.results_accepted = m.results_accepted();
    s.results_dropped_session = m.results_dropped();
    s.merge = m.merge_latency();
    if (const SubmitBudget* budget = m.submit_budget()) s.submit_memory = budget->counters();
    s.store = store_status(coordinator_);
    return prometheus_text(s);
  }

  /// True when the request names a host of this server (docs/security.md, "DNS rebinding"): its
  /// Host, and for requests with a body its Origin when it sends one; otherwise answers 403 and
  /// returns false. Requests without Host (HTTP/1.0 tools) pass: a browser always sends one.
  bool host_allowed(const HttpRequest& req, HttpResponse& res) const {
    if (req.has_header("Host") && !hosts_.allows_host(req.header("Host"))) {
      send_error(res, 403,
                 "Host \"" + printable(req.header("Host")) +
                     "\" is not an address of this server: use its IP address or localhost, or "
                     "start the server with --allowed-host NAME");
      return false;
    }
    if (DashboardRoutes::carries_body(req.method) && req.has_header("Origin") &&
        !hosts_.allows_origin(req.header("Origin"))) {
      send_error(res, 403,
                 "Origin \"" + printable(req.header("Origin")) +
                     "\" may not change this server: only pages it serves itself (or a host "
                     "given with --allowed-host) may");
      return false;
    }
    return true;
  }

  Coordinator& coordinator() { return coordinator_; }

 private:
  double job_rate(const JobRecord& job) const {
    if (job.state != JobState::running) return 0.0;
    return metrics_.job_samples_per_s(job.id, job.started_unix_ms);
  }

  std::optional<double> job_error(const JobRecord& job) {
    if (job.counters.results_merged == 0) return std::nullopt;
    return tile_map(job)->relative_error;
  }

  /// The job's tile map, from a cache: recomputed when more results were merged, but while the
  /// job runs at most once per max(1 s, 10 x the time the last computation took), so that pages
  /// polling a huge job (every tile decoded each time) cost the server about a tenth of a core
  /// at most.
  std::shared_ptr<const TileMap> tile_map(const JobRecord& job) {
    const int64_t now = coordinator_.clock().now_unix_ms();
    {
      std::lock_guard lock(mu_);
      auto it = maps_.find(job.id);
      if (it != maps_.end()) {
        const CachedMap& c = it->second;
        if (c.results_merged == job.counters.results_merged && c.state == job.state) return c.map;
        // A final job changes no more: its last map is computed once, never served stale.
        if (!is_final(job.state) &&
            now - c.computed_unix_ms < std::max<int64_t>(1000, 10 * c.cost_ms)) {
          return c.map;
        }
      }
    }
    const auto t0 = std::chrono::steady_clock::now();
    auto map = std::make_shared<const TileMap>(coordinator_.tile_map(job.id));
    const int64_t cost_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                                std::chrono::steady_clock::now() - t0).count();
    std::lock_guard lock(mu_);
    if (maps_.size() >= kMaxCachedMaps && !maps_.contains(job.id)) {
      // Forget the job computed longest ago.
      auto oldest = std::min_element(maps_.begin(), maps_.end(), [](const auto& a, const auto& b) {
        return a.second.computed_unix_ms < b.second.computed_unix_ms;
      });
      maps_.erase(oldest);
    }
    maps_[job.id] = CachedMap{job.counters.results_merged, job.state, now, cost_ms, map};
    return map;
  }

  struct CachedMap {
    uint32_t results_merged = 0;
    JobState state = JobState::queued;
    int64_t computed_unix_ms = 0;
    int64_t cost_ms = 0;
    std::shared_ptr<const TileMap> map;
  };
  static constexpr size_t kMaxCachedMaps = 256;

  Coordinator& coordinator_;
  const FarmMetrics& metrics_;
  const DashboardConfig config_;
  const HostCheck hosts_;
  std::mutex mu_;  ///< guards maps_ (handlers run on a thread pool)
  std::map<int64_t, CachedMap> maps_;
};

namespace {

/// Paths anyone may read, token or not: the page and what it loads (it asks for the token),
/// and the probes.
bool is_open_path(const std::string& path) {
  if (DashboardRoutes::is_probe(path)) return true;
  return std::any_of(std::begin(dashboard_assets::kAssets), std::end(dashboard_assets::kAssets),
                     [&](const dashboard_assets::Asset& asset) { return asset.path == path; });
}

/// A route pattern (a regex) matching `path` alone.
std::string exact_route(std::string_view path) {
  std::string pattern;
  for (const char c : path) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '/' && c != '_' && c != '-') pattern += '\\';
    pattern += c;
  }
  return pattern;
}

void send_image(DashboardApi& api, const HttpRequest& req, HttpResponse& res,
                const std::string& format) {
  api.guarded(res, [&] {
    // ?denoised=1: a --denoise job's denoised image (the file when done, else denoised now).
    const JobImage image =
        api.coordinator().image(job_id_of(req), format, req.param("denoised") == "1");
    res.set_header("Cache-Control", "no-store");
    res.set_header("X-Tessera-Final", image.final ? "true" : "false");
    res.set_header("X-Tessera-Spp", std::to_string(image.spp));
    res.set_content(image.bytes, format == "png" ? "image/png" : "image/x-exr");
  });
}

}  // namespace

json job_json(const JobRecord& job, int64_t now_unix_ms, double samples_per_s) {
  const uint64_t total = samples_total(job);
  // ETA from the recent rate, else the average since the start.
  json eta = nullptr;
  if (job.state == JobState::running) {
    double rate = samples_per_s;
    const double elapsed_s =
        job.started_unix_ms > 0 ? double(now_unix_ms - job.started_unix_ms) / 1000.0 : 0.0;
    if (rate <= 0 && elapsed_s > 0) rate = double(job.counters.samples_merged) / elapsed_s;
    if (rate > 0) {
      const uint64_t left = total > job.counters.samples_merged ? total - job.counters.samples_merged : 0;
      eta = double(left) / rate;
    }
  } else if (job.state == JobState::done) {
    eta = 0.0;
  }
  // The job's one schema (wire/job_json.h), then only what a live view adds.
  json j = wire::job_json(to_proto(job));
  j["samples_total"] = total;
  j["samples_per_s"] = samples_per_s;
  j["eta_s"] = eta;
  j["tile_count"] = job.tile_count;
  j["batch_count"] = job.batch_count;
  j["renderer_versions"] = job.versions;
  j["preview_url"] = "/api/jobs/" + std::to_string(job.id) + "/preview.png";
  j["image_url"] = "/api/jobs/" + std::to_string(job.id) + "/image.exr";
  return j;
}

json tiles_json(const std::vector<TileView>& tiles) {
  json list = json::array();
  for (const TileView& t : tiles) {
    list.push_back(json{{"tile", t.tile},
                        {"x0", t.rect.x0},
                        {"y0", t.rect.y0},
                        {"x1", t.rect.x1},
                        {"y1", t.rect.y1},
                        {"batches_merged", t.batches_merged},
                        {"spp", t.spp_merged},
                        {"relative_error", optional_number(t.relative_error)}});
  }
  return list;
}

bool DashboardRoutes::is_probe(std::string_view path) {
  return path == "/healthz" || path == "/readyz";
}

bool DashboardRoutes::carries_body(std::string_view method) {
  return method == "POST" || method == "PUT" || method == "PATCH" || method == "DELETE";
}

void DashboardRoutes::body_too_large(HttpResponse& res) {
  send_error(res, 413, "the body may be at most " + std::to_string(kMaxBodyBytes) + " bytes");
}

// Runs on the request's head alone, before any body is read (docs/security.md, "The dashboard"):
// Host and Origin (403), the token (401), then for requests with a body its type (415), a
// declared length (411) and its size (413). The probes pass the first two: they tell nothing and
// change nothing, and an orchestrator probing by a name no --allowed-host lists must not restart
// a healthy server.
bool DashboardRoutes::answer_head(const HttpRequest& req, HttpResponse& res) const {
  if (is_probe(req.path)) return false;
  if (!api_->host_allowed(req, res)) return true;
  if (!is_open_path(req.path) && !api_->authorised(req, res)) return true;
  if (!carries_body(req.method)) return false;
  // A JSON body type also keeps cross-site forms out (they cannot send it without a CORS
  // preflight, which this server never grants).
  if (req.header("Content-Type").rfind("application/json", 0) != 0) {
    send_error(res, 415, "requests that change state must be sent as application/json");
    return true;
  }
  const bool chunked = req.header("Transfer-Encoding").find("chunked") != std::string::npos;
  if (!req.has_header("Content-Length")) {
    if (chunked) return false;  // the listener stops reading past kMaxBodyBytes (413)
    send_error(res, 411, "send the body's length (Content-Length)");
    return true;
  }
  const std::string length = req.header("Content-Length");
  if (length.empty() || length.find_first_not_of("0123456789") != std::string::npos) {
    send_error(res, 400, "Content-Length must be a number of bytes (got \"" + length + "\")");
    return true;
  }
  if (length.size() > 7 || std::stoul(length) > kMaxBodyBytes) {
    send_error(res, 413, "the body may be at most " + std::to_string(kMaxBodyBytes) +
                             " bytes (Content-Length " + length + ")");
    return true;
  }
  return false;
}

void DashboardRoutes::answer(HttpRequest req, HttpResponse& res) const {
  // HEAD is GET without the body (the listener leaves it out).
  const std::string method = req.method == "HEAD" ? "GET" : req.method;
  for (const Route& route : routes_) {
    if (route.method != method) continue;
    std::smatch match;
    if (!std::regex_match(req.path, match, route.pattern)) continue;
    req.matches.assign(match.begin(), match.end());
    route.handler(req, res);
    return;
  }
  // Everything else (unknown paths, wrong methods): a JSON error, never an empty body.
  send_error(res, 404, "not found: " + printable(req.path));
}

DashboardRoutes::~DashboardRoutes() = default;

DashboardRoutes::DashboardRoutes(Coordinator& coordinator, const FarmMetrics& metrics,
                                 DashboardConfig config, HostCheck hosts)
    : api_(std::make_shared<DashboardApi>(coordinator, metrics, std::move(config),
                                          std::move(hosts))) {
  using Handler = std::function<void(const HttpRequest&, HttpResponse&)>;
  auto add = [this](std::string method, const std::string& pattern, Handler handler) {
    routes_.push_back(Route{std::move(method), std::regex(pattern), std::move(handler)});
  };
  const std::shared_ptr<DashboardApi> api = api_;

  for (const dashboard_assets::Asset& asset : dashboard_assets::kAssets) {
    add("GET", exact_route(asset.path), [asset](const HttpRequest&, HttpResponse& res) {
      res.set_header("Cache-Control", "no-cache");
      res.set_content(std::string(asset.body.data(), asset.body.size()),
                      std::string(asset.content_type));
    });
  }

  add("GET", "/api/jobs", [api](const HttpRequest& req, HttpResponse& res) {
    api->guarded(res, [&] { send_json(res, 200, api->jobs(job_query(req))); });
  });
  add("GET", R"(/api/jobs/(\d+))", [api](const HttpRequest& req, HttpResponse& res) {
    api->guarded(res, [&] { send_json(res, 200, api->job_detail(job_id_of(req))); });
  });
  add("GET", R"(/api/jobs/(\d+)/preview\.png)", [api](const HttpRequest& req, HttpResponse& res) {
    send_image(*api, req, res, "png");
  });
  add("GET", R"(/api/jobs/(\d+)/image\.exr)", [api](const HttpRequest& req, HttpResponse& res) {
    send_image(*api, req, res, "exr");
  });
  // Bodies were read by the listener, at most kMaxBodyBytes of them (a chunked body, whose
  // length no header declares, is cut off there with 413).
  add("POST", R"(/api/jobs/(\d+)/cancel)", [api](const HttpRequest& req, HttpResponse& res) {
    api->guarded(res, [&] {
      const JobRecord job = api->coordinator().cancel(job_id_of(req));
      send_json(res, 200, api->job_summary(job, api->coordinator().clock().now_unix_ms()));
    });
  });
  add("POST", R"(/api/jobs/(\d+)/priority)", [api](const HttpRequest& req, HttpResponse& res) {
    api->guarded(res, [&] {
      const json body = json::parse(req.body, nullptr, /*allow_exceptions=*/false);
      if (!body.is_object() || !body.contains("priority") ||
          !body["priority"].is_number_integer() ||
          body["priority"].get<int64_t>() < INT_MIN ||
          body["priority"].get<int64_t>() > INT_MAX) {
        throw FarmError(ErrorCode::invalid_argument,
                        "body must be {\"priority\": INTEGER} (a 32-bit integer)");
      }
      const JobRecord job = api->coordinator().set_priority(
          job_id_of(req), int(body["priority"].get<int64_t>()));
      send_json(res, 200, api->job_summary(job, api->coordinator().clock().now_unix_ms()));
    });
  });
  add("GET", "/api/store", [api](const HttpRequest&, HttpResponse& res) {
    api->guarded(res, [&] { send_json(res, 200, store_json(store_status(api->coordinator()))); });
  });
  add("GET", "/api/workers", [api](const HttpRequest&, HttpResponse& res) {
    api->guarded(res, [&] { send_json(res, 200, api->workers()); });
  });
  add("GET", "/metrics", [api](const HttpRequest&, HttpResponse& res) {
    api->guarded(res, [&] {
      res.set_content(api->metrics_text(), "text/plain; version=0.0.4; charset=utf-8");
    });
  });
  add("GET", "/healthz", [](const HttpRequest&, HttpResponse& res) {
    send_json(res, 200, json{{"status", "ok"}});
  });
  add("GET", "/readyz", [api](const HttpRequest&, HttpResponse& res) {
    const bool stopped = api->coordinator().changes().stopped();
    const std::string why = stopped ? "" : api->coordinator().store_unready_reason();
    const bool ready = !stopped && why.empty();
    json body{{"status", ready ? "ready" : "not ready"}};
    if (!why.empty()) body["reason"] = why;
    send_json(res, ready ? 200 : 503, body);
  });
}

}  // namespace tessera::server
