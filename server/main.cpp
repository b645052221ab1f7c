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
#include "cli/host_port.h"
#include "cli/usage_exit.h"
#include "listen_policy.h"
#include "store/db_lock.h"
#include "store/integrity.h"
#include "wire/bearer_token.h"
#include "wire/rpc_channel.h"
#include "wire/transport_security.h"
#include "worker_service.h"

namespace {

struct Flags {
  std::string grpc_address = "127.0.0.1:50051";
  std::string http_address = "127.0.0.1:8080";
  std::string db = "var/tessera.db";
  std::string token, token_file;                // both services
  std::string worker_token, worker_token_file;  // WorkerService only (overrides --token there)
  std::string client_token, client_token_file;  // JobService only (overrides --token there)
  tessera::wire::ServerTls tls;
  bool insecure = false;
  std::string output_dir = "var/outputs";
  double lease_seconds = 30;
  double shutdown_seconds = 30;
  std::string port_file;
  tessera::server::FarmLimits limits;
  double max_bundle_mb = 512;
  tessera::server::WorkerHealthPolicy health;
  double forgive_seconds = 600;
  double nan_report_fraction = 1e-3;
  double retention_days = 0;  ///< --retention-days (0: keep finished jobs)
  uint64_t merge_cache_mb = 1024;  ///< --merge-cache-mb
  std::string http_port_file;
};

/// The tokens each service requires, after --token, the role tokens and their files.
struct Tokens {
  std::string worker, client;
};

Tokens resolve_tokens(const Flags& flags) {
  namespace tw = tessera::wire;
  const std::string shared = tw::resolve_token(flags.token, flags.token_file, "--token");
  Tokens tokens;
  tokens.worker = tw::resolve_token(flags.worker_token, flags.worker_token_file, "--worker-token");
  tokens.client = tw::resolve_token(flags.client_token, flags.client_token_file, "--client-token");
  if (tokens.worker.empty()) tokens.worker = shared;
  if (tokens.client.empty()) tokens.client = shared;
  if (!tokens.worker.empty() && tokens.worker == tokens.client &&
      (!flags.worker_token.empty() || !flags.worker_token_file.empty()) &&
      (!flags.client_token.empty() || !flags.client_token_file.empty())) {
    throw std::runtime_error(
        "--worker-token and --client-token are the same: use --token for one shared token");
  }
  return tokens;
}

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

int serve(const Flags& flags, const sigset_t& stop_signals) {
  namespace ts = tessera::server;
  ts::call_trace::start_from_environment();  // measurement only (server/call_trace.h)
  const Tokens tokens = resolve_tokens(flags);
  check_grpc_listen_policy(flags, tokens);
  // The dashboard needs the client token for everything but its page and probes
  // (docs/security.md). Without one it may not listen beyond loopback either. It speaks HTTPS
  // with --tls-cert. (The flags' check has refused a malformed --http address already.)
  {
    const std::string warning = tessera::server::check_listen_policy(
        flags.http_address, tokens.client.empty() ? "the dashboard (HTTP)" : "", flags.tls.active(),
        flags.insecure);
    if (!warning.empty()) std::cerr << "tessera-server: warning: " << warning << std::endl;
  }
  const std::shared_ptr<grpc::ServerCredentials> credentials =
      tessera::wire::server_credentials(flags.tls);
  if (flags.db != ":memory:") {
    const auto parent = std::filesystem::path(flags.db).parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent);
  }
  // Before the database is opened: a second server on it is refused, naming the holder.
  const ts::DatabaseLock db_lock(flags.db);
  ts::SystemClock clock;
  ts::CoordinatorConfig config;
  config.db_path = flags.db;
  config.output_dir = flags.output_dir;
  config.lease_ms = int64_t(flags.lease_seconds * 1000.0);
  config.limits = flags.limits;
  config.limits.max_bundle_bytes = uint64_t(flags.max_bundle_mb * 1024.0 * 1024.0);
  config.health = flags.health;
  config.health.forgive_ms = int64_t(flags.forgive_seconds * 1000.0);
  config.nan_report_fraction = flags.nan_report_fraction;
  config.retention_days = flags.retention_days;
  config.merge_cache_bytes = size_t(flags.merge_cache_mb) << 20;
  ts::FarmMetrics metrics(clock);  // the dashboard's rates, fed by every answered upload
  ts::Coordinator coordinator(config, clock);
  coordinator.set_upload_observer(&metrics);
  const int resumed = coordinator.resume();

  tessera::wire::BearerTokenCheck client_auth(tokens.client);
  tessera::wire::BearerTokenCheck worker_auth(tokens.worker);
  ts::JobServiceImpl job_service(coordinator, client_auth);
  ts::WorkerServiceImpl worker_service(coordinator, worker_auth);

  // The standard health service answers without a token (orchestrators probe it; it says only
  // SERVING). Reflection describes the API to anyone who asks, so it is offered only when no
  // token is required.
  grpc::EnableDefaultHealthCheckService(true);
  const bool open = !client_auth.enabled() && !worker_auth.enabled();
  if (open) grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  int port = 0;
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
  const std::string host = flags.grpc_address.substr(0, flags.grpc_address.rfind(':'));
  std::string security =
      flags.tls.active() ? (flags.tls.client_ca_file.empty() ? ", TLS" : ", mutual TLS") : "";
  if (client_auth.enabled() || worker_auth.enabled()) {
    security += tokens.client == tokens.worker ? ", token required"
                : !client_auth.enabled()       ? ", worker token required"
                : !worker_auth.enabled()       ? ", client token required"
                                               : ", client and worker tokens required";
  }
  std::cout << "tessera-server: listening on " << host << ":" << port << " (db " << flags.db << ", "
            << resumed << " unfinished job(s) resumed" << security << ")" << std::endl;

  // The dashboard (server/dashboard/): page, JSON API, /metrics, probes.
  // With --tls-cert/--tls-key it serves HTTPS with the same certificate as gRPC.
  ts::DashboardConfig dashboard_config;
  dashboard_config.token = tokens.client;
  if (flags.tls.active()) {
    dashboard_config.tls_cert_file = flags.tls.cert_file;
    dashboard_config.tls_key_file = flags.tls.key_file;
  }
  std::optional<ts::DashboardServer> dashboard;
  int http_port = 0;
  try {
    dashboard.emplace(coordinator, metrics, std::move(dashboard_config));
    http_port = dashboard->start(flags.http_address);
  } catch (const std::exception& e) {
    std::cerr << "tessera-server: " << e.what() << "\n";
    server->Shutdown();
    return 1;
  }
  const std::string http_host = flags.http_address.substr(0, flags.http_address.rfind(':'));
  std::cout << "tessera-server: dashboard on " << (flags.tls.active() ? "https" : "http") << "://"
            << http_host << ":" << http_port << "/"
            << std::endl;
  if (!flags.http_port_file.empty()) write_port_file(flags.http_port_file, http_port);
  // Last: the gRPC port file tells scripts that both listeners are up.
  if (!flags.port_file.empty()) write_port_file(flags.port_file, port);
  // OpenImageIO's ~260 libraries are most of what start-up would cost (BENCHMARKS.md, "Server
  // start-up time"): loaded now, beside serving, so that the first preview does not wait for them.
  // Joined before serve() returns (never unloaded mid-exit).
  std::thread image_module_loader([] {
    try {
      const auto began = std::chrono::steady_clock::now();
      ts::load_image_module();
      // tests/load/load_test.cpp waits for this line: the server's CPU after it is what serving
      // costs, without the module's load.
      std::cout << "tessera-server: image module loaded ("
                << std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count()
                << " s)" << std::endl;
    } catch (const std::exception& e) {
      std::cerr << "tessera-server: warning: " << e.what() << " (tried again at the first image)"
                << std::endl;
    }
  });
  struct JoinLoader {
    std::thread& thread;
    ~JoinLoader() { thread.join(); }
  } join_loader{image_module_loader};

  const auto reap_period = std::chrono::milliseconds(
      std::clamp<int64_t>(coordinator.lease_ms() / 4, 50, 1000));
  auto reaper = std::make_unique<ts::LeaseReaper>(coordinator, reap_period);

  // Signals were blocked in every thread; this one takes SIGINT/SIGTERM synchronously.
  std::thread signal_thread([&] {
    int signal_number = 0;
    sigwait(&stop_signals, &signal_number);
    std::cout << "tessera-server: signal " << signal_number
              << ", shutting down: no new leases; waiting up to " << flags.shutdown_seconds
              << " s for calls in flight (uploads commit)" << std::endl;
    coordinator.stop_leasing();  // ends long polls and watches at once
    dashboard->stop();
    server->Shutdown(std::chrono::system_clock::now() +
                     std::chrono::milliseconds(int64_t(flags.shutdown_seconds * 1000.0)));
  });
  server->Wait();
  signal_thread.join();
  reaper.reset();
  const bool clean = coordinator.checkpoint();
  if (!ts::call_trace::write()) std::cerr << "tessera-server: warning: call trace not written\n";
  std::cout << "tessera-server: stopped"
            << (clean ? " (WAL checkpointed)"
                      : " (WAL checkpoint incomplete: replayed at next start)")
            << std::endl;
  return 0;
}

template <typename T>
CLI::Option* limit_option(CLI::App& app, const std::string& name, T& target, const std::string& env,
                          const std::string& help) {
  return app.add_option(name, target, help)->envname(env)->capture_default_str();
}

}  // namespace

int main(int argc, char** argv) {
  // gRPC locks absl::Mutex many times per call. The distribution's Abseil is built without NDEBUG,
  // so each lock also updated Abseil's global lock-order graph (its deadlock detector, a share of the
  // server's CPU in every profile: BENCHMARKS.md, "What a result and a job cost the server, counted"). The
  // server's own locks are std::mutex; nothing here relies on that detector.
  absl::SetMutexDeadlockDetectionMode(absl::OnDeadlockCycle::kIgnore);
  CLI::App app{"tessera-server: the render farm's coordinator (gRPC API, SQLite job store)"};
  app.set_version_flag("--version", "tessera-server " + tessera::build_version(),
                       "Print the version, commit and compiler, and exit");
  Flags flags;
  app.add_option("--grpc", flags.grpc_address, "gRPC listen address HOST:PORT (port 0: any free)")
      ->envname("TESSERA_GRPC")
      ->check(tessera::cli::host_port_check())
      ->capture_default_str();
  app.add_option("--http", flags.http_address,
                 "HTTP dashboard, JSON API and /metrics address HOST:PORT (port 0: any free)")
      ->envname("TESSERA_HTTP")
      ->check(tessera::cli::host_port_check())
      ->capture_default_str();
  app.add_option("--db", flags.db, "SQLite database file (created if missing)")
      ->envname("TESSERA_DB")
      ->capture_default_str();

  // Authentication and transport (docs/security.md).
  app.add_option(
         "--token", flags.token,
         "shared secret: every call of both services must carry 'authorization: Bearer TOKEN'")
      ->envname("TESSERA_TOKEN");
  app.add_option("--token-file", flags.token_file, "read --token from this file (first line)")
      ->envname("TESSERA_TOKEN_FILE");
  app.add_option("--worker-token", flags.worker_token,
                 "token of the worker service only (replaces --token there)")
      ->envname("TESSERA_WORKER_TOKEN");
  app.add_option("--worker-token-file", flags.worker_token_file,
                 "read --worker-token from this file")
      ->envname("TESSERA_WORKER_TOKEN_FILE");
  app.add_option("--client-token", flags.client_token,
                 "token of the job service (CLI, dashboard) only (replaces --token there)")
      ->envname("TESSERA_CLIENT_TOKEN");
  app.add_option("--client-token-file", flags.client_token_file,
                 "read --client-token from this file")
      ->envname("TESSERA_CLIENT_TOKEN_FILE");
  app.add_option("--tls-cert", flags.tls.cert_file, "serve TLS with this PEM certificate chain")
      ->envname("TESSERA_TLS_CERT");
  app.add_option("--tls-key", flags.tls.key_file, "PEM private key of --tls-cert")
      ->envname("TESSERA_TLS_KEY");
  app.add_option("--tls-client-ca", flags.tls.client_ca_file,
                 "mutual TLS: require every peer to present a certificate signed by this PEM CA")
      ->envname("TESSERA_TLS_CLIENT_CA");
  app.add_flag("--insecure", flags.insecure,
               "allow a non-loopback --grpc address without tokens (logged as a warning)")
      ->envname("TESSERA_INSECURE");

  app.add_option("--output-dir", flags.output_dir, "where finished jobs' EXR and PNG are written")
      ->envname("TESSERA_OUTPUT_DIR")
      ->capture_default_str();
  app.add_option("--lease-seconds", flags.lease_seconds,
                 "lease length in seconds; workers heartbeat every third of it")
      ->envname("TESSERA_LEASE_SECONDS")
      ->check(CLI::Range(0.1, 86400.0))
      ->capture_default_str();
  app.add_option("--shutdown-seconds", flags.shutdown_seconds,
                 "on SIGTERM, how long calls in flight (uploads) may take to finish")
      ->envname("TESSERA_SHUTDOWN_SECONDS")
      ->check(CLI::Range(0.0, 3600.0))
      ->capture_default_str();
  app.add_option("--port-file", flags.port_file,
                 "write the gRPC port chosen to this file once listening (for --grpc HOST:0)")
      ->envname("TESSERA_PORT_FILE");

  // Limits (docs/security.md, "Limits").
  auto& limits = flags.limits;
  limit_option(app, "--max-bundle-mb", flags.max_bundle_mb, "TESSERA_MAX_BUNDLE_MB",
               "largest scene bundle (sum of its files), MiB")
      ->check(CLI::Range(0.001, 1000.0));
  limit_option(app, "--max-bundle-files", limits.max_bundle_files, "TESSERA_MAX_BUNDLE_FILES",
               "most files in a scene bundle")
      ->check(CLI::PositiveNumber);
  limit_option(app, "--max-triangles", limits.max_triangles, "TESSERA_MAX_TRIANGLES",
               "most triangles in a scene (mesh headers checked before they are read)")
      ->check(CLI::PositiveNumber);
  limit_option(app, "--max-image-size", limits.job.max_dimension, "TESSERA_MAX_IMAGE_SIZE",
               "largest image width and height, pixels")
      ->check(CLI::Range(1, 32768));
  limit_option(app, "--max-spp", limits.job.max_spp, "TESSERA_MAX_SPP", "most samples per pixel")
      ->check(CLI::Range(int64_t(1), int64_t(1) << 31));
  limit_option(app, "--max-tile", limits.job.max_tile, "TESSERA_MAX_TILE",
               "largest tile size, pixels")
      ->check(CLI::Range(1, 4096));
  limit_option(app, "--max-queued-jobs", limits.max_queued_jobs_per_client,
               "TESSERA_MAX_QUEUED_JOBS", "most unfinished jobs per client host (0: no limit)");
  limit_option(app, "--max-units", limits.max_units_per_job, "TESSERA_MAX_UNITS",
               "most work units (tiles x batches) per job")
      ->check(CLI::Range(uint64_t(1), uint64_t(1) << 22));
  limit_option(app, "--max-pixels", limits.max_pixels_per_job, "TESSERA_MAX_PIXELS",
               "most pixels (width x height) per job; the server holds a job's whole image when "
               "it writes it, about 70 bytes a pixel")
      ->check(CLI::Range(uint64_t(1), uint64_t(32768) * 32768));

  // Worker health (docs/reliability.md).
  limit_option(app, "--block-after-failures", flags.health.failures_to_block,
               "TESSERA_BLOCK_AFTER_FAILURES",
               "failed units of one job that block a worker from it")
      ->check(CLI::Range(1, 1000));
  limit_option(app, "--block-forgive-seconds", flags.forgive_seconds,
               "TESSERA_BLOCK_FORGIVE_SECONDS",
               "a block lapses this long after the worker's last failure on the job")
      ->check(CLI::Range(0.0, 30.0 * 86400.0));
  limit_option(app, "--unit-fail-workers", flags.health.workers_to_fail_unit,
               "TESSERA_UNIT_FAIL_WORKERS", "different workers failing one unit that fail its job")
      ->check(CLI::Range(1, 1000));
  limit_option(app, "--nan-report-fraction", flags.nan_report_fraction,
               "TESSERA_NAN_REPORT_FRACTION",
               "report a worker whose NaN/Inf samples exceed this fraction of its samples")
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--merge-cache-mb", flags.merge_cache_mb,
                 "memory for decoded tiles kept between merges, MiB (36 bytes per pixel); a"
                 " quarter of it more for decoded results waiting for an earlier batch")
      ->envname("TESSERA_MERGE_CACHE_MB")
      ->capture_default_str();
  app.add_option("--retention-days", flags.retention_days,
                 "delete finished, failed and cancelled jobs this many days after they ended"
                 " (0: keep them)")
      ->envname("TESSERA_RETENTION_DAYS")
      ->check(CLI::Range(0.0, 36500.0))
      ->capture_default_str();
  app.add_option("--http-port-file", flags.http_port_file,
                 "write the HTTP port chosen to this file once listening (for --http HOST:0)")
      ->envname("TESSERA_HTTP_PORT_FILE");
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
