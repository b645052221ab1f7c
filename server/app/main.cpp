// tessera-server: the farm's coordinator (docs/farm.md). gRPC for clients and workers, SQLite
// store, scheduler, leases, in-order merge, image output. Security (tokens, TLS, limits) is
// described in docs/security.md; shutdown and worker health in docs/reliability.md.
#include <absl/synchronization/mutex.h>
#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/grpcpp.h>
#include <grpcpp/health_check_service_interface.h>
#include <signal.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <thread>

#include "build_info.h"
#include "call_trace.h"
#include "coordinator.h"
#include "dashboard/farm_metrics.h"
#include "dashboard/http_server.h"
#include "job_service.h"
#include "lazy_image_io.h"
#include "lease_reaper.h"
#include "cli/usage_exit.h"
#include "listen_policy.h"
#include "server_flags.h"
#include "store/db_lock.h"
#include "store/integrity.h"
#include "wire/bearer_token.h"
#include "wire/rpc_channel.h"
#include "wire/transport_security.h"
#include "worker_service.h"

namespace {

using tessera::server::Flags;
using tessera::server::Tokens;

/// Refuses to expose an unauthenticated service beyond this machine (docs/security.md).
void check_grpc_listen_policy(const Flags& flags, const Tokens& tokens) {
  std::string missing;
  if (tokens.client.empty()) missing = "clients (JobService)";
  if (tokens.worker.empty()) {
    missing += std::string(missing.empty() ? "" : " and ") + "workers (WorkerService)";
  }
  const std::string warning = tessera::server::check_listen_policy(
      flags.grpc_address, missing, flags.tls.active(), flags.insecure);
  if (!warning.empty()) std::cerr << "tessera-server: warning: " << warning << std::endl;
}

void write_port_file(const std::string& path, int port) {
  const std::string temp = path + ".partial";
  {
    std::ofstream out(temp);
    out << port << "\n";
    if (!out) throw std::runtime_error(temp + ": cannot write");
  }
  std::filesystem::rename(temp, path);
}

// gRPC's synchronous server runs each call on a thread of its pool and by default keeps at most
// 2 idle ones polling for calls: the rest end when their call does, so under 64-256 workers
// nearly every call started a thread of its own (about 1,000 threads created per second of
// tessera-bench-merge). Idle threads up to this many stay and take the next calls
// (BENCHMARKS.md, "Lease latency and capacity"; counted by
// ServerThreadsE2E.IdleThreadsServeTheNextCalls).
constexpr int kMaxPollers = 256;

/// Warns of a dashboard listening beyond loopback without the client token (docs/security.md):
/// it needs that token for everything but its page and probes.
void check_http_listen_policy(const Flags& flags, const Tokens& tokens) {
  const std::string warning = tessera::server::check_listen_policy(
      flags.http_address, tokens.client.empty() ? "the dashboard (HTTP)" : "", flags.tls.active(),
      flags.insecure);
  if (!warning.empty()) std::cerr << "tessera-server: warning: " << warning << std::endl;
}

/// The gRPC server with both services, listening; nullptr (and `port` 0) when it cannot listen.
std::unique_ptr<grpc::Server> start_grpc(
    const Flags& flags, const std::shared_ptr<grpc::ServerCredentials>& credentials,
    grpc::Service& job_service, grpc::Service& worker_service, bool reflection, int& port) {
  // The standard health service answers without a token (orchestrators probe it; it says only
  // SERVING). Reflection describes the API to anyone who asks, so it is offered only when no
  // token is required.
  grpc::EnableDefaultHealthCheckService(true);
  if (reflection) grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  builder.AddListeningPort(flags.grpc_address, credentials, &port);
  builder.SetMaxReceiveMessageSize(tessera::wire::kMaxMessageBytes);
  builder.SetMaxSendMessageSize(tessera::wire::kMaxMessageBytes);
  builder.AddChannelArgument(GRPC_ARG_KEEPALIVE_TIME_MS, tessera::wire::kKeepaliveTimeMs);
  builder.AddChannelArgument(GRPC_ARG_KEEPALIVE_TIMEOUT_MS, tessera::wire::kKeepaliveTimeoutMs);
  builder.AddChannelArgument(GRPC_ARG_KEEPALIVE_PERMIT_WITHOUT_CALLS, 1);
  // gRPC sets SO_REUSEPORT by default: the kernel may then give port 0's "free" port to two
  // processes at once (seen in tests beside other farms), and a client reaches the wrong one.
  builder.AddChannelArgument(GRPC_ARG_ALLOW_REUSEPORT, 0);
  // Accept the clients' keepalive pings (every kKeepaliveTimeMs) without calling them abusive.
  builder.AddChannelArgument(GRPC_ARG_HTTP2_MIN_RECV_PING_INTERVAL_WITHOUT_DATA_MS,
                             tessera::wire::kKeepaliveTimeMs / 3);
  builder.SetSyncServerOption(grpc::ServerBuilder::SyncServerOption::MAX_POLLERS, kMaxPollers);
  builder.RegisterService(&job_service);
  builder.RegisterService(&worker_service);
  std::unique_ptr<grpc::Server> server = builder.BuildAndStart();
  if (!server) port = 0;
  return server;
}

/// The line that says the server listens: where, on which store, what it resumed, and what a
/// caller needs (TLS, tokens).
void print_listening(const Flags& flags, const Tokens& tokens, bool client_auth,
                     bool worker_auth, int port, int resumed) {
  const std::string host = flags.grpc_address.substr(0, flags.grpc_address.rfind(':'));
  std::string security =
      flags.tls.active() ? (flags.tls.client_ca_file.empty() ? ", TLS" : ", mutual TLS") : "";
  if (client_auth || worker_auth) {
    security += tokens.client == tokens.worker ? ", token required"
                : !client_auth                 ? ", worker token required"
                : !worker_auth                 ? ", client token required"
                                               : ", client and worker tokens required";
  }
  std::cout << "tessera-server: listening on " << host << ":" << port << " (db " << flags.db << ", "
            << resumed << " unfinished job(s) resumed" << security << ")" << std::endl;
}

/// The dashboard (server/dashboard/): page, JSON API, /metrics, probes; HTTPS with the gRPC
/// certificate under --tls-cert/--tls-key. Throws when it cannot listen.
std::unique_ptr<tessera::server::DashboardServer> start_dashboard(
    const Flags& flags, const Tokens& tokens, tessera::server::Coordinator& coordinator,
    tessera::server::FarmMetrics& metrics) {
  tessera::server::DashboardConfig config;
  config.token = tokens.client;
  if (flags.tls.active()) {
    config.tls_cert_file = flags.tls.cert_file;
    config.tls_key_file = flags.tls.key_file;
  }
  config.allowed_hosts = flags.allowed_hosts;
  config.limits.connections_per_client = flags.http_connections_per_client;
  config.limits.head_timeout_ms = int64_t(flags.http_head_timeout_s * 1000.0);
  auto dashboard =
      std::make_unique<tessera::server::DashboardServer>(coordinator, metrics, std::move(config));
  const int http_port = dashboard->start(flags.http_address);
  const std::string http_host = flags.http_address.substr(0, flags.http_address.rfind(':'));
  std::cout << "tessera-server: dashboard on " << (flags.tls.active() ? "https" : "http") << "://"
            << http_host << ":" << http_port << "/" << std::endl;
  if (!flags.http_port_file.empty()) write_port_file(flags.http_port_file, http_port);
  return dashboard;
}

/// OpenImageIO's ~260 libraries are most of what start-up costs (BENCHMARKS.md, "Server start-up
/// time"): loaded on a thread of their own while the store opens and resumes, and waited for
/// before the server listens. Not after: while dlopen maps them it holds the dynamic loader's
/// lock, which every new thread takes (its TLS), and gRPC's server starts a thread as a call
/// arrives, so a server listening meanwhile answered nothing for the length of the load
/// (0.4-0.9 s on 2 busy cores, seconds on busier ones) and workers came back that much later.
class ImageModuleLoader {
 public:
  ImageModuleLoader() : thread_(load) {}
  ~ImageModuleLoader() { wait(); }
  /// Returns once the module is loaded (or its load failed and was reported).
  void wait() {
    if (thread_.joinable()) thread_.join();
  }

 private:
  static void load() {
    try {
      const auto began = std::chrono::steady_clock::now();
      tessera::server::load_image_module();
      std::cout << "tessera-server: image module loaded ("
                << std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count()
                << " s)" << std::endl;
    } catch (const std::exception& e) {
      std::cerr << "tessera-server: warning: " << e.what() << " (tried again at the first image)"
                << std::endl;
    }
  }
  std::thread thread_;
};

/// Serves until SIGINT or SIGTERM, then shuts down gracefully: no new leases, calls in flight
/// (uploads) get up to --shutdown-seconds.
void serve_until_stopped(const Flags& flags, const sigset_t& stop_signals,
                         tessera::server::Coordinator& coordinator,
                         tessera::server::DashboardServer& dashboard, grpc::Server& server) {
  const auto reap_period = std::chrono::milliseconds(
      std::clamp<int64_t>(coordinator.lease_ms() / 4, 50, 1000));
  auto reaper = std::make_unique<tessera::server::LeaseReaper>(coordinator, reap_period);
  // Signals were blocked in every thread; this one takes SIGINT/SIGTERM synchronously.
  std::thread signal_thread([&] {
    int signal_number = 0;
    sigwait(&stop_signals, &signal_number);
    std::cout << "tessera-server: signal " << signal_number
              << ", shutting down: no new leases; waiting up to " << flags.shutdown_seconds
              << " s for calls in flight (uploads commit)" << std::endl;
    coordinator.stop_leasing();  // ends long polls and watches at once
    dashboard.stop();
    server.Shutdown(std::chrono::system_clock::now() +
                    std::chrono::milliseconds(int64_t(flags.shutdown_seconds * 1000.0)));
  });
  server.Wait();
  signal_thread.join();
  reaper.reset();
}

int serve(const Flags& flags, const sigset_t& stop_signals) {
  namespace ts = tessera::server;
  ts::call_trace::start_from_environment();  // measurement only (server/call_trace.h)
  const Tokens tokens = resolve_tokens(flags);
  check_grpc_listen_policy(flags, tokens);
  check_http_listen_policy(flags, tokens);
  const std::shared_ptr<grpc::ServerCredentials> credentials =
      tessera::wire::server_credentials(flags.tls);
  if (flags.db != ":memory:") {
    const auto parent = std::filesystem::path(flags.db).parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent);
  }
  // Before the database is opened: a second server on it is refused, naming the holder.
  const ts::DatabaseLock db_lock(flags.db);
  ImageModuleLoader image_module_loader;  // beside the store's opening; waited for below
  ts::SystemClock clock;
  ts::FarmMetrics metrics(clock);  // the dashboard's rates, fed by every answered upload
  // The server's memory budget: submit checks and denoises (server/job_denoise.h) reserve in it.
  ts::SubmitBudget submit_budget(flags.submit_memory_mb << 20);
  ts::CoordinatorConfig config = coordinator_config(flags);
  config.denoise = std::make_shared<ts::JobDenoise>(
      tessera::oidn_library_candidates_for_flag(flags.oidn_library), &submit_budget);
  ts::Coordinator coordinator(config, clock);
  coordinator.set_upload_observer(&metrics);
  const int resumed = coordinator.resume();

  tessera::wire::BearerTokenCheck client_auth(tokens.client);
  tessera::wire::BearerTokenCheck worker_auth(tokens.worker);
  metrics.set_submit_budget(&submit_budget);
  ts::JobServiceImpl job_service(coordinator, client_auth,
                                 {&submit_budget, flags.max_texture_values});
  ts::WorkerServiceImpl worker_service(coordinator, worker_auth);
  image_module_loader.wait();  // before listening: no call waits behind the dynamic loader
  int port = 0;
  const bool open = !client_auth.enabled() && !worker_auth.enabled();
  std::unique_ptr<grpc::Server> server =
      start_grpc(flags, credentials, job_service, worker_service, open, port);
  if (!server || port == 0) {
    std::cerr << "tessera-server: cannot listen on " << flags.grpc_address << "\n";
    return 1;
  }
  // Damage found by the background check of the store (after an unclean stop) turns the
  // standard health service to NOT_SERVING, as /readyz turns 503 (docs/reliability.md).
  coordinator.set_damage_observer([&server](const std::string&) {
    server->GetHealthCheckService()->SetServingStatus(false);
  });
  struct ObserverReset {  // before `server` goes: no call into it after that
    ts::Coordinator& coordinator;
    ~ObserverReset() { coordinator.set_damage_observer(nullptr); }
  } observer_reset{coordinator};
  print_listening(flags, tokens, client_auth.enabled(), worker_auth.enabled(), port, resumed);
  std::unique_ptr<ts::DashboardServer> dashboard;
  try {
    dashboard = start_dashboard(flags, tokens, coordinator, metrics);
  } catch (const std::exception& e) {
    std::cerr << "tessera-server: " << e.what() << "\n";
    server->Shutdown();
    return 1;
  }
  // Last: the gRPC port file tells scripts that both listeners are up.
  if (!flags.port_file.empty()) write_port_file(flags.port_file, port);
  serve_until_stopped(flags, stop_signals, coordinator, *dashboard, *server);
  const bool clean = coordinator.checkpoint();
  if (!ts::call_trace::write()) std::cerr << "tessera-server: warning: call trace not written\n";
  std::cout << "tessera-server: stopped"
            << (clean ? " (WAL checkpointed)"
                      : " (WAL checkpoint incomplete: replayed at next start)")
            << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // gRPC locks absl::Mutex many times per call. The distribution's Abseil is built without NDEBUG,
  // so each lock also updated Abseil's global lock-order graph (its deadlock detector, a share of
  // the server's CPU in every profile: BENCHMARKS.md, "What a result and a job cost the server,
  // counted"). The server's own locks are std::mutex; nothing here relies on that detector.
  absl::SetMutexDeadlockDetectionMode(absl::OnDeadlockCycle::kIgnore);
  CLI::App app{"tessera-server: the render farm's coordinator (gRPC API, SQLite job store)"};
  app.set_version_flag("--version", "tessera-server " + tessera::build_version(),
                       "Print the version, commit and compiler, and exit");
  tessera::server::Flags flags;
  tessera::server::add_server_flags(app, flags);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return tessera::cli::exit_for_parse_error(app, e, "tessera-server");
  }

  // Block the stop signals before any thread starts, so only sigwait sees them.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
  try {
    return serve(flags, stop_signals);
  } catch (const tessera::server::SqliteError& e) {
    if (tessera::server::is_corruption(e)) {
      std::cerr << "tessera-server: " << tessera::server::corrupt_store_message(flags.db, e.what())
                << "\n";
    } else {
      std::cerr << "tessera-server: " << flags.db << ": " << e.what() << "\n";
    }
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "tessera-server: " << e.what() << "\n";
    return 1;
  }
}
