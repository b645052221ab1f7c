#include "dashboard/api.h"

#include <httplib.h>
#include <openssl/crypto.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>

#include "coordinator.h"
#include "dashboard/prometheus_text.h"
#include "dashboard_assets.h"
#include "farm_error.h"
#include "job_output.h"
#include "wire/job_options_wire.h"

namespace tessera::server {
namespace {

using nlohmann::json;

json optional_number(std::optional<double> v) { return v ? json(*v) : json(nullptr); }

uint64_t samples_total(const JobRecord& job) {
  return uint64_t(job.options.width) * uint64_t(job.options.height) * job.options.spp;
}

void send_json(httplib::Response& res, int status, const json& body) {
  res.status = status;
  res.set_header("Cache-Control", "no-store");
  res.set_content(body.dump(), "application/json");
}

void send_error(httplib::Response& res, int status, const std::string& message) {
  send_json(res, status, json{{"error", message}});
}

int status_of(ErrorCode code) {
  switch (code) {
    case ErrorCode::invalid_argument: return 400;
    case ErrorCode::not_found: return 404;
    case ErrorCode::failed_precondition: return 409;
    case ErrorCode::internal: return 500;
  }
  return 500;
}

/// The {id} of a route: digits only (the route's regex), 1..INT64_MAX. Throws FarmError.
int64_t job_id_of(const httplib::Request& req) {
  const std::string& text = req.matches[1].str();
  if (text.size() > 18 || std::stoll(text) < 1) {
    throw FarmError(ErrorCode::not_found, "no job " + text);
  }
  return std::stoll(text);
}

/// Everything the routes share; owned by the handlers' closures.
class Api {
 public:
  Api(Coordinator& coordinator, DashboardConfig config)
      : coordinator_(coordinator), config_(std::move(config)) {}

  /// Runs a handler, mapping FarmError and other exceptions to JSON errors.
  template <typename F>
  void guarded(httplib::Response& res, F&& handler) {
    try {
      handler();
    } catch (const FarmError& e) {
      send_error(res, status_of(e.code()), e.what());
    } catch (const std::exception& e) {
      send_error(res, 500, e.what());
    }
  }

  /// True when the request may change state; otherwise answers 401/415 and returns false.
  bool authorised_change(const httplib::Request& req, httplib::Response& res) const {
    // A JSON body type keeps cross-site forms out even without a token (they cannot send it
    // without a CORS preflight, which this server never grants).
    if (req.get_header_value("Content-Type").rfind("application/json", 0) != 0) {
      send_error(res, 415, "requests that change state must be sent as application/json");
      return false;
    }
    if (config_.token.empty()) return true;
    const std::string expected = "Bearer " + config_.token;
    const std::string given = req.get_header_value("Authorization");
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

  json jobs(uint32_t limit) {
    const int64_t now = coordinator_.clock().now_unix_ms();
    json list = json::array();
    for (const JobRecord& job : coordinator_.jobs(limit)) list.push_back(job_summary(job, now));
    return json{{"jobs", list},
                {"server_time_unix_ms", now},
                {"token_required", !config_.token.empty()},
                {"samples_per_s", coordinator_.metrics().farm_samples_per_s()}};
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
          {"state", !online ? "offline" : w.job_id ? "busy" : "idle"},
          {"online", online},
          {"unit", unit},
          {"samples_per_s", coordinator_.metrics().worker_samples_per_s(w.id)},
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
    s.totals = coordinator_.totals();
    for (const WorkerRecord& w : coordinator_.workers()) s.workers_online += coordinator_.online(w);
    const FarmMetrics& m = coordinator_.metrics();
    s.samples_per_s = m.farm_samples_per_s();
    s.results_accepted = m.results_accepted();
    s.results_dropped_session = m.results_dropped();
    s.merge = m.merge_latency();
    return prometheus_text(s);
  }

  Coordinator& coordinator() { return coordinator_; }

 private:
  double job_rate(const JobRecord& job) const {
    if (job.state != JobState::running) return 0.0;
    return coordinator_.metrics().job_samples_per_s(job.id, job.started_unix_ms);
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
  const DashboardConfig config_;
  std::mutex mu_;  ///< guards maps_ (handlers run on a thread pool)
  std::map<int64_t, CachedMap> maps_;
};

void send_image(Api& api, const httplib::Request& req, httplib::Response& res,
                const std::string& format) {
  api.guarded(res, [&] {
    const JobImage image = api.coordinator().image(job_id_of(req), format);
    res.set_header("Cache-Control", "no-store");
    res.set_header("X-Tessera-Final", image.final ? "true" : "false");
    res.set_header("X-Tessera-Spp", std::to_string(image.spp));
    res.set_content(image.bytes, format == "png" ? "image/png" : "image/x-exr");
  });
}

}  // namespace

json job_json(const JobRecord& job, int64_t now_unix_ms, double samples_per_s) {
  const uint64_t total = samples_total(job);
  double elapsed_s = 0;
  if (job.started_unix_ms > 0) {
    const int64_t end = job.finished_unix_ms > 0 ? job.finished_unix_ms : now_unix_ms;
    elapsed_s = std::max<double>(0, double(end - job.started_unix_ms) / 1000.0);
  }
  // ETA from the recent rate, else the average since the start.
  json eta = nullptr;
  if (job.state == JobState::running) {
    double rate = samples_per_s;
    if (rate <= 0 && elapsed_s > 0) rate = double(job.counters.samples_merged) / elapsed_s;
    if (rate > 0) {
      const uint64_t left = total > job.counters.samples_merged ? total - job.counters.samples_merged : 0;
      eta = double(left) / rate;
    }
  } else if (job.state == JobState::done) {
    eta = 0.0;
  }
  const JobCounters& c = job.counters;
  return json{
      {"id", job.id},
      {"state", std::string(to_string(job.state))},
      {"priority", job.priority},
      {"scene_file", job.scene_file},
      {"bundle_sha256", job.bundle_sha256},
      {"options", json::parse(wire::options_to_json(job.options))},
      {"progress", job.progress()},
      {"spp_merged", job.spp_merged},
      {"spp_target", job.options.spp},
      // The stopping rule and what the job reached (docs/accuracy.md): per-tile spp and error.
      {"stop_rule", std::string(to_string(job.options.rule))},
      {"time_budget_s", job.options.time_budget_s},
      {"noise_target", job.options.noise_target},
      {"stop_reason", std::string(to_string(job.stop_reason))},
      {"reached",
       {{"spp_min", job.reached.spp_min},
        {"spp_mean", job.reached.spp_mean},
        {"spp_max", job.reached.spp_max},
        {"error_max", job.reached.error_max},
        {"error_mean", job.reached.error_mean},
        {"tiles_finished", job.tiles_finished}}},
      {"samples_merged", c.samples_merged},
      {"samples_total", total},
      {"samples_per_s", samples_per_s},
      {"elapsed_s", elapsed_s},
      {"eta_s", eta},
      {"tile_count", job.tile_count},
      {"batch_count", job.batch_count},
      {"counters",
       {{"units_total", job.units_total},
        {"units_done", c.units_done},
        {"units_leased", c.units_leased},
        {"results_merged", c.results_merged},
        {"results_dropped", c.results_dropped},
        {"leases_expired", c.leases_expired},
        {"units_released", c.units_released},
        {"units_skipped", c.units_skipped},
        {"results_wasted", c.results_wasted},
        {"nan_dropped", c.nan_dropped},
        {"inf_dropped", c.inf_dropped}}},
      {"submitted_unix_ms", job.submitted_unix_ms},
      {"started_unix_ms", job.started_unix_ms},
      {"finished_unix_ms", job.finished_unix_ms},
      {"error", job.error},
      {"isas", job.isas},
      {"renderer_versions", job.versions},
      {"preview_url", "/api/jobs/" + std::to_string(job.id) + "/preview.png"},
      {"image_url", "/api/jobs/" + std::to_string(job.id) + "/image.exr"},
  };
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

void install_dashboard_routes(httplib::Server& http, Coordinator& coordinator,
                              DashboardConfig config) {
  auto api = std::make_shared<Api>(coordinator, std::move(config));

  auto asset = [](std::string_view body, const char* type) {
    return [body, type](const httplib::Request&, httplib::Response& res) {
      res.set_header("Cache-Control", "no-cache");
      res.set_content(body.data(), body.size(), type);
    };
  };
  http.Get("/", asset(dashboard_assets::dashboard_html, "text/html; charset=utf-8"));
  http.Get("/dashboard.js", asset(dashboard_assets::dashboard_js, "text/javascript; charset=utf-8"));
  http.Get("/dashboard.css", asset(dashboard_assets::dashboard_css, "text/css; charset=utf-8"));

  http.Get("/api/jobs", [api](const httplib::Request& req, httplib::Response& res) {
    api->guarded(res, [&] {
      uint32_t limit = 1000;
      if (req.has_param("limit")) {
        const std::string text = req.get_param_value("limit");
        if (text.empty() || text.size() > 6 || text.find_first_not_of("0123456789") != std::string::npos ||
            std::stoul(text) == 0) {
          throw FarmError(ErrorCode::invalid_argument, "limit must be 1..999999 (got \"" + text + "\")");
        }
        limit = uint32_t(std::stoul(text));
      }
      send_json(res, 200, api->jobs(limit));
    });
  });
  http.Get(R"(/api/jobs/(\d+))", [api](const httplib::Request& req, httplib::Response& res) {
    api->guarded(res, [&] { send_json(res, 200, api->job_detail(job_id_of(req))); });
  });
  http.Get(R"(/api/jobs/(\d+)/preview\.png)",
           [api](const httplib::Request& req, httplib::Response& res) {
             send_image(*api, req, res, "png");
           });
  http.Get(R"(/api/jobs/(\d+)/image\.exr)",
           [api](const httplib::Request& req, httplib::Response& res) {
             send_image(*api, req, res, "exr");
           });
  http.Post(R"(/api/jobs/(\d+)/cancel)", [api](const httplib::Request& req, httplib::Response& res) {
    if (!api->authorised_change(req, res)) return;
    api->guarded(res, [&] {
      const JobRecord job = api->coordinator().cancel(job_id_of(req));
      send_json(res, 200, api->job_summary(job, api->coordinator().clock().now_unix_ms()));
    });
  });
  http.Post(R"(/api/jobs/(\d+)/priority)",
            [api](const httplib::Request& req, httplib::Response& res) {
              if (!api->authorised_change(req, res)) return;
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
  http.Get("/api/workers", [api](const httplib::Request&, httplib::Response& res) {
    api->guarded(res, [&] { send_json(res, 200, api->workers()); });
  });
  http.Get("/metrics", [api](const httplib::Request&, httplib::Response& res) {
    api->guarded(res, [&] {
      res.set_content(api->metrics_text(), "text/plain; version=0.0.4; charset=utf-8");
    });
  });
  http.Get("/healthz", [](const httplib::Request&, httplib::Response& res) {
    send_json(res, 200, json{{"status", "ok"}});
  });
  http.Get("/readyz", [api](const httplib::Request&, httplib::Response& res) {
    const bool ready = !api->coordinator().changes().stopped() && api->coordinator().store_ready();
    send_json(res, ready ? 200 : 503, json{{"status", ready ? "ready" : "not ready"}});
  });
  // Everything else (unknown paths, wrong methods): a JSON error, never an empty body.
  http.set_error_handler([](const httplib::Request& req, httplib::Response& res) {
    if (!res.body.empty()) return;
    const std::string what = res.status == 404 ? "not found: " + req.path
                             : res.status == 405 ? "method not allowed: " + req.method + " " + req.path
                                                 : "HTTP error " + std::to_string(res.status);
    send_json(res, res.status, json{{"error", what}});
  });
}

}  // namespace tessera::server
