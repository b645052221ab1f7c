// The dashboard's HTTP API against a real tessera-server on loopback (label e2e): every endpoint,
// unknown ids, the token on every read and change, and requests refused on their headers before
// any body is read. The server binds 127.0.0.1:0 for
// HTTP and writes the port it got (FarmCluster reads it).
#include <gtest/gtest.h>
#include <httplib.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <csignal>
#include <fstream>
#include <nlohmann/json.hpp>

#include "exr_header.h"
#include "farm_cluster.h"
#include "loopback_socket.h"
#include "image/image_output.h"

namespace tessera::e2e {
namespace {

using nlohmann::json;

const std::string kTiny = (source_dir() / "tests" / "farm" / "data" / "tiny.json").string();

/// Sends `head` (request line and headers, no body) over a fresh connection and returns the
/// status code of the answer, or -1 when none came: the server must answer from the headers
/// alone. The 60 s receive limit only bounds a failing test.
int status_from_headers_only(int port, const std::string& head) {
  const int fd = connect_to_loopback(port);
  if (fd < 0) return -1;
  int status = -1;
  if (::send(fd, head.data(), head.size(), MSG_NOSIGNAL) == ssize_t(head.size())) {
    std::string got;
    char buf[512];
    while (got.find("\r\n") == std::string::npos) {
      const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
      if (n <= 0) break;
      got.append(buf, size_t(n));
    }
    // "HTTP/1.1 413 Payload Too Large"
    if (got.starts_with("HTTP/1.") && got.size() >= 12) status = std::stoi(got.substr(9, 3));
  }
  ::close(fd);
  return status;
}

std::string post_head(const std::string& path, const std::vector<std::string>& headers) {
  std::string head = "POST " + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\n";
  for (const std::string& h : headers) head += h + "\r\n";
  return head + "\r\n";
}

class DashboardApi : public ::testing::Test {
 protected:
  httplib::Client client() {
    httplib::Client c("127.0.0.1", farm_->http_port());
    c.set_read_timeout(60, 0);
    c.set_connection_timeout(10, 0);
    return c;
  }
  /// GET that must succeed at the HTTP level; returns the response.
  httplib::Result get(const std::string& path) {
    httplib::Client c = client();
    httplib::Result r = c.Get(path.c_str());
    EXPECT_TRUE(r) << path << ": " << httplib::to_string(r.error());
    return r;
  }
  /// GET with `Authorization: Bearer token`.
  httplib::Result get_with_token(const std::string& path, const std::string& token) {
    httplib::Client c = client();
    httplib::Result r = c.Get(path.c_str(), {{"Authorization", "Bearer " + token}});
    EXPECT_TRUE(r) << path << ": " << httplib::to_string(r.error());
    return r;
  }
  json get_json(const std::string& path, int expected_status = 200) {
    httplib::Result r = get(path);
    if (!r) return {};
    EXPECT_EQ(r->status, expected_status) << path << ": " << r->body;
    EXPECT_EQ(r->get_header_value("Content-Type"), "application/json") << path;
    return json::parse(r->body);
  }
  httplib::Result post(const std::string& path, const std::string& body,
                       const std::string& token = "",
                       const std::string& type = "application/json") {
    httplib::Client c = client();
    httplib::Headers headers;
    if (!token.empty()) headers.emplace("Authorization", "Bearer " + token);
    httplib::Result r = c.Post(path.c_str(), headers, body, type.c_str());
    EXPECT_TRUE(r) << path;
    return r;
  }
  void expect_json_error(const httplib::Result& r, int status, const std::string& needle) {
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, status) << r->body;
    const json body = json::parse(r->body, nullptr, false);
    ASSERT_TRUE(body.is_object() && body.contains("error")) << r->body;
    EXPECT_NE(body["error"].get<std::string>().find(needle), std::string::npos) << r->body;
  }

  std::unique_ptr<FarmCluster> farm_;
};

TEST_F(DashboardApi, EveryReadEndpointOnAFinishedJob) {
  farm_ = std::make_unique<FarmCluster>("dashboard-api-read");
  farm_->start_server();
  farm_->start_worker({"--threads", "1"});
  const std::vector<std::string> options = {"--spp", "8", "--batch", "2", "--tile", "8"};
  std::vector<std::string> submit_args = {kTiny};
  submit_args.insert(submit_args.end(), options.begin(), options.end());
  const uint64_t id = farm_->submit(submit_args);
  const v1::JobInfo done = farm_->wait_final(id);
  ASSERT_EQ(done.state(), v1::JOB_STATE_DONE);
  const std::string job_path = "/api/jobs/" + std::to_string(id);

  EXPECT_EQ(get_json("/healthz")["status"], "ok");
  EXPECT_EQ(get_json("/readyz")["status"], "ready");

  const json list = get_json("/api/jobs");
  ASSERT_EQ(list["jobs"].size(), 1u);
  const json& summary = list["jobs"][0];
  EXPECT_EQ(summary["id"], id);
  EXPECT_EQ(summary["state"], "done");
  EXPECT_EQ(summary["progress"], 1.0);
  EXPECT_EQ(summary["spp_merged"], 8);
  EXPECT_EQ(summary["stop_rule"], "spp");
  EXPECT_EQ(summary["stop_reason"], "spp_reached");
  EXPECT_EQ(summary["reached"]["spp_min"], 8);
  EXPECT_EQ(summary["reached"]["spp_max"], 8);
  EXPECT_EQ(summary["counters"]["samples_merged"], 16 * 16 * 8);
  EXPECT_EQ(summary["samples_total"], 16 * 16 * 8);
  EXPECT_EQ(summary["counters"]["units_done"], 4 * 4);
  EXPECT_EQ(summary["options"]["batch_spp"], 2);
  EXPECT_TRUE(summary["relative_error"].is_number());
  EXPECT_GT(summary["relative_error"].get<double>(), 0.0);
  EXPECT_FALSE(list["token_required"].get<bool>());
  // A new store: no check was due, nothing damaged, it writes, and the CLI warns of nothing.
  EXPECT_EQ(list["store"], (json{{"state", "ok"}, {"check", "none"}, {"check_progress", nullptr},
                                 {"damage", ""}, {"leasing", true}, {"write_error", ""}}));
  EXPECT_EQ(get_json("/api/store"), list["store"]);
  const CommandResult listed = farm_->cli({"list"});
  EXPECT_EQ(listed.exit_code, 0) << listed.err;
  EXPECT_EQ(listed.err, "");

  const json detail = get_json(job_path);
  ASSERT_EQ(detail["tiles"].size(), 4u);  // 16x16 in 8x8 tiles
  double largest_tile_error = 0;
  for (const json& t : detail["tiles"]) {
    EXPECT_EQ(t["spp"], 8);
    EXPECT_EQ(t["batches_merged"], 4);
    EXPECT_EQ(t["x1"].get<int>() - t["x0"].get<int>(), 8);
    ASSERT_TRUE(t["relative_error"].is_number()) << t;
    largest_tile_error = std::max(largest_tile_error, t["relative_error"].get<double>());
  }
  EXPECT_GT(largest_tile_error, 0.0);
  // The job's error is the one `tessera-worker render` reports for the same (bit-identical) sums.
  std::vector<std::string> render_args = {kTiny, "-q", "-o", (farm_->dir() / "local.exr").string()};
  render_args.insert(render_args.end(), options.begin(), options.end());
  const CommandResult local = farm_->local_render(render_args);
  ASSERT_EQ(local.exit_code, 0) << local.err;
  const std::string local_error =
      image_attribute(farm_->dir() / "local.exr", "tessera:estimated_relative_error");
  ASSERT_FALSE(local_error.empty());
  EXPECT_NEAR(detail["relative_error"].get<double>(), std::stod(local_error), 1e-6);
  EXPECT_EQ(detail["provenance"]["tessera:scene_sha256"], done.bundle_sha256());
  // One schema for a job: every key of `tessera status --json` is in the API's job,
  // with the same value (the job is done: nothing moves any more).
  const CommandResult status = farm_->cli({"status", std::to_string(id), "--json"});
  ASSERT_EQ(status.exit_code, 0) << status.err;
  const json cli = json::parse(status.out);
  EXPECT_GE(cli.size(), 20u);
  for (const auto& [key, value] : cli.items()) {
    ASSERT_TRUE(detail.contains(key)) << key;
    EXPECT_EQ(detail[key], value) << key;
  }
  EXPECT_EQ(detail["provenance"]["tessera:spp"], "8");

  // The preview of a done job is its final PNG; the EXR is the file the server wrote.
  httplib::Result png = get(job_path + "/preview.png");
  ASSERT_TRUE(png);
  EXPECT_EQ(png->status, 200);
  EXPECT_EQ(png->get_header_value("Content-Type"), "image/png");
  EXPECT_EQ(png->get_header_value("X-Tessera-Final"), "true");
  EXPECT_EQ(png->body.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  const auto png_path = farm_->dir() / "preview.png";
  std::ofstream(png_path, std::ios::binary) << png->body;
  const RgbImage decoded = read_image(png_path);
  EXPECT_EQ(decoded.width, 16);
  EXPECT_EQ(decoded.height, 16);

  httplib::Result exr = get(job_path + "/image.exr");
  ASSERT_TRUE(exr);
  EXPECT_EQ(exr->status, 200);
  EXPECT_EQ(exr->get_header_value("Content-Type"), "image/x-exr");
  std::ifstream written(done.output_exr(), std::ios::binary);
  const std::string file((std::istreambuf_iterator<char>(written)), {});
  EXPECT_FALSE(file.empty());
  EXPECT_EQ(exr->body, file);

  const json workers = get_json("/api/workers");
  ASSERT_EQ(workers["workers"].size(), 1u);
  const json& w = workers["workers"][0];
  EXPECT_EQ(w["name"], "e2e-worker-0");
  EXPECT_EQ(w["threads"], 1);
  EXPECT_EQ(w["units_done"], 16);
  EXPECT_EQ(w["units_held"], 0);  // every result in
  EXPECT_EQ(w["failures"], 0);
  EXPECT_TRUE(w["online"].get<bool>());
  EXPECT_TRUE(w["state"] == "idle" || w["state"] == "busy");
  // Alone of its build: nothing checked (its results merged unverified), not quarantined.
  EXPECT_TRUE(w["quarantine"].is_null());
  EXPECT_EQ(w["checks"], 0);
  EXPECT_EQ(w["mismatches"], 0);
  // The job is pinned to its one worker's renderer build, which is online.
  EXPECT_EQ(detail["pinned_build"], w["version"]);
  EXPECT_FALSE(detail["waiting_for_build"].get<bool>());

  httplib::Result metrics = get("/metrics");
  ASSERT_TRUE(metrics);
  EXPECT_EQ(metrics->status, 200);
  EXPECT_NE(metrics->get_header_value("Content-Type").find("text/plain; version=0.0.4"),
            std::string::npos);
  EXPECT_NE(metrics->body.find("tessera_jobs{state=\"done\"} 1\n"), std::string::npos);
  EXPECT_NE(metrics->body.find("tessera_units_done_total 16\n"), std::string::npos);
  EXPECT_NE(metrics->body.find("tessera_merge_latency_seconds_count 16\n"), std::string::npos);
  EXPECT_NE(metrics->body.find("tessera_spot_checks_total{outcome=\"checked\"} 0\n"),
            std::string::npos);

  // The page and its assets come from the binary.
  httplib::Result page = get("/");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->status, 200);
  EXPECT_NE(page->body.find("<script type=\"module\" src=\"/dashboard.js\">"), std::string::npos);
  for (const std::string path : {"/dashboard.css", "/dashboard.js", "/js/api.js", "/js/job_detail.js",
                                 "/js/jobs_list.js", "/js/workers_list.js"}) {
    httplib::Result asset = get(path);
    ASSERT_TRUE(asset) << path;
    EXPECT_EQ(asset->status, 200) << path;
  }
  EXPECT_EQ(get("/js/api.js")->get_header_value("Content-Type"), "text/javascript; charset=utf-8");
  EXPECT_EQ(get("/js/apixjs")->status, 404);  // a route is its path, not a pattern
}

TEST_F(DashboardApi, UnknownIdsAndPathsAre404WithAJsonError) {
  farm_ = std::make_unique<FarmCluster>("dashboard-api-404");
  farm_->start_server();
  expect_json_error(get("/api/jobs/999"), 404, "no job 999");
  expect_json_error(get("/api/jobs/999/preview.png"), 404, "no job 999");
  expect_json_error(get("/api/jobs/999/image.exr"), 404, "no job 999");
  expect_json_error(get("/api/jobs/0"), 404, "no job 0");
  expect_json_error(get("/api/jobs/99999999999999999999"), 404, "no job");
  expect_json_error(get("/api/jobs/abc"), 404, "not found: /api/jobs/abc");
  expect_json_error(get("/nothing-here"), 404, "not found: /nothing-here");
  expect_json_error(post("/api/jobs/999/cancel", "{}"), 404, "no job 999");
  expect_json_error(post("/api/jobs/999/priority", R"({"priority": 1})"), 404, "no job 999");
  expect_json_error(get("/api/jobs?limit=0"), 400, "limit must be");
  EXPECT_EQ(get_json("/api/jobs")["jobs"].size(), 0u);
  EXPECT_EQ(get_json("/api/workers")["workers"].size(), 0u);
}

// With a client token, every read needs it too; only the page and the probes are open.
TEST_F(DashboardApi, EveryReadAndChangeNeedsTheTokenButThePageAndProbes) {
  const std::string token = "dashboard-secret";
  farm_ = std::make_unique<FarmCluster>("dashboard-api-token");
  farm_->start_server({"--token", token});
  // No worker: the job stays queued while we poke at it.
  const uint64_t id = farm_->submit({kTiny, "--spp", "64"});
  const std::string job_path = "/api/jobs/" + std::to_string(id);

  const std::vector<std::string> guarded = {"/api/jobs", job_path, job_path + "/preview.png",
                                            job_path + "/image.exr", "/api/workers", "/metrics",
                                            "/api/store",
                                            "/api/jobs/999", "/api/nothing"};
  for (const std::string& path : guarded) {
    SCOPED_TRACE(path);
    httplib::Result r = get(path);
    expect_json_error(r, 401, "needs a token");
    EXPECT_EQ(r->get_header_value("WWW-Authenticate"), "Bearer");
    expect_json_error(get_with_token(path, "wrong"), 401, "wrong token");
  }
  for (const std::string path :
       {"/", "/dashboard.js", "/dashboard.css", "/js/api.js", "/healthz", "/readyz"}) {
    httplib::Result r = get(path);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200) << path;
  }
  httplib::Result listed = get_with_token("/api/jobs", token);
  ASSERT_TRUE(listed);
  ASSERT_EQ(listed->status, 200) << listed->body;
  const json list = json::parse(listed->body);
  EXPECT_TRUE(list["token_required"].get<bool>());
  EXPECT_EQ(list["jobs"][0]["state"], "queued");
  httplib::Result preview = get_with_token(job_path + "/preview.png", token);
  ASSERT_TRUE(preview);
  EXPECT_EQ(preview->status, 200);
  EXPECT_EQ(preview->get_header_value("X-Tessera-Final"), "false");
  httplib::Result metrics = get_with_token("/metrics", token);  // Prometheus' bearer_token
  ASSERT_TRUE(metrics);
  EXPECT_EQ(metrics->status, 200);

  httplib::Result r = post(job_path + "/cancel", "{}");
  expect_json_error(r, 401, "needs a token");
  EXPECT_EQ(r->get_header_value("WWW-Authenticate"), "Bearer");
  expect_json_error(post(job_path + "/cancel", "{}", "wrong"), 401, "wrong token");
  expect_json_error(post(job_path + "/cancel", "{}", token + "x"), 401, "wrong token");
  expect_json_error(post(job_path + "/priority", R"({"priority": 9})"), 401, "token");
  expect_json_error(post(job_path + "/cancel", "{}", token, "text/plain"), 415, "application/json");
  EXPECT_EQ(farm_->job(id).state(), v1::JOB_STATE_QUEUED);
  EXPECT_EQ(farm_->job(id).priority(), 0);

  expect_json_error(post(job_path + "/priority", R"({"priority": "high"})", token), 400,
                    "priority");
  expect_json_error(post(job_path + "/priority", "not json", token), 400, "priority");
  expect_json_error(post(job_path + "/priority", R"({"priority": 4294967296})", token), 400,
                    "32-bit");
  r = post(job_path + "/priority", R"({"priority": 7})", token);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(json::parse(r->body)["priority"], 7);
  EXPECT_EQ(farm_->job(id).priority(), 7);

  r = post(job_path + "/cancel", "{}", token);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(json::parse(r->body)["state"], "cancelled");
  EXPECT_EQ(farm_->job(id).state(), v1::JOB_STATE_CANCELLED);
  expect_json_error(post(job_path + "/cancel", "{}", token), 409, "already cancelled");
  expect_json_error(post(job_path + "/priority", R"({"priority": 1})", token), 409,
                    "already cancelled");
}

TEST(DashboardListener, ABadOrBusyAddressStopsTheServerWithOneLine) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("tessera-dashboard-listen-" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  // Hold a port the way a second server would.
  httplib::Server holder;
  const int busy = holder.bind_to_any_port("127.0.0.1");
  ASSERT_GT(busy, 0);
  auto server = [&](const std::string& http, const std::string& stem) {
    return run_command({TESSERA_SERVER_BIN, "--grpc", "127.0.0.1:0", "--http", http, "--db",
                        (dir / (stem + ".db")).string()},
                       dir / stem, {}, kPatience);
  };
  CommandResult r = server("127.0.0.1:" + std::to_string(busy), "busy");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("cannot listen on 127.0.0.1:" + std::to_string(busy) + " (HTTP)"),
            std::string::npos) << r.err;
  // A malformed address is a usage error (status 2) naming the flag and what is wrong.
  r = server("no-port-here", "bad");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--http: no-port-here: expected HOST:PORT"), std::string::npos) << r.err;
  r = server("127.0.0.1:70000", "range");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--http: 127.0.0.1:70000: port 70000 is out of range [0, 65535]"),
            std::string::npos) << r.err;
  std::filesystem::remove_all(dir);
}

// An output folder that cannot be created (a regular file where it should be): the job is done,
// and the API, `tessera status` and its --json say "output not written" and name no files until
// they exist; once the folder can be made, `tessera get` has them written and the paths appear.
TEST_F(DashboardApi, AnOutputThatCannotBeWrittenIsShownUntilItIs) {
  farm_ = std::make_unique<FarmCluster>("dashboard-api-output-error");
  farm_->start_server();
  const std::filesystem::path outputs = farm_->dir() / "outputs";
  std::filesystem::remove_all(outputs);
  std::ofstream(outputs) << "not a folder";
  farm_->start_worker({"--threads", "1"});
  const uint64_t id = farm_->submit({kTiny, "--spp", "2", "--tile", "8"});
  ASSERT_EQ(farm_->wait_final(id).state(), v1::JOB_STATE_DONE);
  const std::string job_path = "/api/jobs/" + std::to_string(id);

  const json job = get_json(job_path);
  EXPECT_EQ(job["state"], "done");
  EXPECT_EQ(job["error"], "");
  EXPECT_NE(job["output_error"].get<std::string>().find(outputs.string() + ": cannot create: "),
            std::string::npos)
      << job.dump();
  EXPECT_EQ(job["output_exr"], "");
  EXPECT_EQ(job["output_png"], "");
  EXPECT_EQ(get_json("/api/jobs")["jobs"][0]["output_error"], job["output_error"]);

  const CommandResult status = farm_->cli({"status", std::to_string(id)});
  EXPECT_EQ(status.exit_code, 0) << status.err;
  EXPECT_NE(status.out.find("error     output not written: " + outputs.string()),
            std::string::npos)
      << status.out;
  const CommandResult status_json = farm_->cli({"status", std::to_string(id), "--json"});
  const json from_cli = json::parse(status_json.out, nullptr, false);
  ASSERT_TRUE(from_cli.is_object()) << status_json.out << status_json.err;
  EXPECT_EQ(from_cli["output_error"], job["output_error"]);

  // The folder can be made now: `get` writes the files, and the job names them.
  std::filesystem::remove(outputs);
  const CommandResult fetched =
      farm_->cli({"get", std::to_string(id), "-o", (farm_->dir() / "fetched.exr").string()});
  EXPECT_EQ(fetched.exit_code, 0) << fetched.err;
  const json written = get_json(job_path);
  EXPECT_EQ(written["output_error"], "");
  EXPECT_EQ(written["output_exr"], (outputs / ("job-" + std::to_string(id) + ".exr")).string());
  EXPECT_TRUE(std::filesystem::exists(written["output_exr"].get<std::string>()));
  EXPECT_TRUE(std::filesystem::exists(written["output_png"].get<std::string>()));
  if (HasFailure()) farm_->dump_logs();
}

TEST_F(DashboardApi, PriorityChangesWhatRunsNext) {
  farm_ = std::make_unique<FarmCluster>("dashboard-api-priority");
  farm_->start_server();
  const uint64_t first = farm_->submit({kTiny, "--spp", "4"});
  const uint64_t second = farm_->submit({kTiny, "--spp", "4"});
  // Without a change the older job runs first; raise the younger one.
  httplib::Result r = post("/api/jobs/" + std::to_string(second) + "/priority", R"({"priority": 5})");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  farm_->start_worker({"--threads", "1"});
  const v1::JobInfo a = farm_->wait_final(first);
  const v1::JobInfo b = farm_->wait_final(second);
  ASSERT_EQ(a.state(), v1::JOB_STATE_DONE);
  ASSERT_EQ(b.state(), v1::JOB_STATE_DONE);
  EXPECT_LT(b.started_unix_ms(), a.started_unix_ms());
}

// A POST's headers decide before any of its body is read, in this order: token 401, type 415,
// no length 411, over 64 KiB 413 (reading a body whole first let a 200 MB body take the server
// from 254 MB to 1.11 GB, and one without Content-Length wait 5 s for a generic 400). Each
// request below sends its headers only: the status must come without the body.
TEST_F(DashboardApi, PostsAreRefusedOnTheirHeadersBeforeAnyBodyIsRead) {
  const std::string token = "body-secret";
  farm_ = std::make_unique<FarmCluster>("dashboard-api-bodies");
  farm_->start_server({"--token", token});
  const int port = farm_->http_port();
  const std::string cancel = "/api/jobs/1/cancel";
  const std::string auth = "Authorization: Bearer " + token;
  const std::string huge = "Content-Length: 200000000";
  const std::string type = "Content-Type: application/json";
  EXPECT_EQ(status_from_headers_only(port, post_head(cancel, {huge, type})), 401);
  EXPECT_EQ(status_from_headers_only(port, post_head(cancel, {huge, "Content-Type: text/plain", "Authorization: Bearer wrong"})), 401);
  EXPECT_EQ(status_from_headers_only(port, post_head(cancel, {huge, "Content-Type: text/plain", auth})), 415);
  EXPECT_EQ(status_from_headers_only(port, post_head(cancel, {huge, auth})), 415);
  EXPECT_EQ(status_from_headers_only(port, post_head(cancel, {type, auth})), 411);
  EXPECT_EQ(status_from_headers_only(port, post_head(cancel, {huge, type, auth})), 413);
  EXPECT_EQ(status_from_headers_only(port, post_head(cancel, {"Content-Length: 65537", type, auth})), 413);
  EXPECT_EQ(status_from_headers_only(port, post_head(cancel, {"Content-Length: 99999999999999999999999", type, auth})), 413);
  EXPECT_EQ(status_from_headers_only(port, post_head(cancel, {"Content-Length: -5", type, auth})), 400);
  // Within the limit the body is read and the request goes on (no job 1: 404).
  expect_json_error(post(cancel, "{}", token), 404, "no job 1");
  // A chunked body is read up to the limit, then refused. The server may close the connection
  // while the client still writes: that must be an error here, not a SIGPIPE.
  std::signal(SIGPIPE, SIG_IGN);
  httplib::Client c = client();
  const std::string big(70 * 1024, ' ');
  httplib::Result r = c.Post(cancel.c_str(), {{"Authorization", "Bearer " + token}},
                             [&](size_t, httplib::DataSink& sink) {  // no length: chunked
                               sink.write(big.data(), big.size());
                               sink.done();
                               return true;
                             },
                             "application/json");
  if (r) {
    EXPECT_EQ(r->status, 413);  // or the connection is closed under the client
  }
  // The server still serves.
  EXPECT_EQ(get_json("/healthz")["status"], "ok");
}

}  // namespace
}  // namespace tessera::e2e
