// tessera-server: the farm's coordinator (docs/farm.md). gRPC for clients and workers, SQLite
// store, scheduler, leases, in-order merge, image output.
#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/grpcpp.h>
#include <grpcpp/health_check_service_interface.h>
#include <signal.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <thread>

#include "coordinator.h"
#include "dashboard/http_server.h"
#include "job_service.h"
#include "lease_reaper.h"
#include "wire/bearer_token.h"
#include "wire/rpc_channel.h"
#include "worker_service.h"

namespace {

struct Flags {
  std::string grpc_address = "127.0.0.1:50051";
  std::string http_address = "127.0.0.1:8080";
  std::string db = "var/tessera.db";
  std::string token;
  std::string output_dir = "var/outputs";
  double lease_seconds = 30;
  std::string port_file;
  std::string http_port_file;
};

void write_port_file(const std::string& path, int port) {
  const std::string temp = path + ".partial";
  {
    std::ofstream out(temp);
    out << port << "\n";
    if (!out) throw std::runtime_error(temp + ": cannot write");
  }
  std::filesystem::rename(temp, path);
}

int serve(const Flags& flags, const sigset_t& stop_signals) {
  namespace ts = tessera::server;
  if (flags.db != ":memory:") {
    const auto parent = std::filesystem::path(flags.db).parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent);
  }
  ts::SystemClock clock;
  ts::CoordinatorConfig config;
  config.db_path = flags.db;
  config.output_dir = flags.output_dir;
  config.lease_ms = int64_t(flags.lease_seconds * 1000.0);
  ts::Coordinator coordinator(config, clock);
  const int resumed = coordinator.resume();

  tessera::wire::BearerTokenCheck auth(flags.token);
  ts::JobServiceImpl job_service(coordinator, auth);
  ts::WorkerServiceImpl worker_service(coordinator, auth);

  grpc::EnableDefaultHealthCheckService(true);
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  int port = 0;
  builder.AddListeningPort(flags.grpc_address, grpc::InsecureServerCredentials(), &port);
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
  builder.RegisterService(&job_service);
  builder.RegisterService(&worker_service);
  std::unique_ptr<grpc::Server> server = builder.BuildAndStart();
  if (!server || port == 0) {
    std::cerr << "tessera-server: cannot listen on " << flags.grpc_address << "\n";
    return 1;
  }
  const std::string host = flags.grpc_address.substr(0, flags.grpc_address.rfind(':'));
  std::cout << "tessera-server: listening on " << host << ":" << port << " (db " << flags.db
            << ", " << resumed << " unfinished job(s) resumed"
            << (auth.enabled() ? ", token required" : "") << ")" << std::endl;

  // The dashboard (server/dashboard/): page, JSON API, /metrics, probes.
  ts::DashboardServer dashboard(coordinator, ts::DashboardConfig{flags.token});
  int http_port = 0;
  try {
    http_port = dashboard.start(flags.http_address);
  } catch (const std::exception& e) {
    std::cerr << "tessera-server: " << e.what() << "\n";
    server->Shutdown();
    return 1;
  }
  const std::string http_host = flags.http_address.substr(0, flags.http_address.rfind(':'));
  std::cout << "tessera-server: dashboard on http://" << http_host << ":" << http_port << "/"
            << std::endl;
  if (!flags.http_port_file.empty()) write_port_file(flags.http_port_file, http_port);
  // Last: the gRPC port file tells scripts that both listeners are up.
  if (!flags.port_file.empty()) write_port_file(flags.port_file, port);

  const auto reap_period = std::chrono::milliseconds(
      std::clamp<int64_t>(coordinator.lease_ms() / 4, 50, 1000));
  ts::LeaseReaper reaper(coordinator, reap_period);

  // Signals were blocked in every thread; this one takes SIGINT/SIGTERM synchronously.
  std::thread signal_thread([&] {
    int signal_number = 0;
    sigwait(&stop_signals, &signal_number);
    std::cout << "tessera-server: signal " << signal_number << ", shutting down" << std::endl;
    coordinator.changes().stop();  // ends long polls and watches at once
    dashboard.stop();
    server->Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(5));
  });
  server->Wait();
  signal_thread.join();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"tessera-server: the render farm's coordinator (gRPC API, SQLite job store)"};
  Flags flags;
  app.add_option("--grpc", flags.grpc_address, "gRPC listen address HOST:PORT (port 0: any free)")
      ->envname("TESSERA_GRPC")
      ->capture_default_str();
  app.add_option("--http", flags.http_address,
                 "HTTP dashboard, JSON API and /metrics address HOST:PORT (port 0: any free)")
      ->envname("TESSERA_HTTP")
      ->capture_default_str();
  app.add_option("--db", flags.db, "SQLite database file (created if missing)")
      ->envname("TESSERA_DB")
      ->capture_default_str();
  app.add_option("--token", flags.token,
                 "shared secret: every call must carry 'authorization: Bearer TOKEN'")
      ->envname("TESSERA_TOKEN");
  app.add_option("--output-dir", flags.output_dir, "where finished jobs' EXR and PNG are written")
      ->envname("TESSERA_OUTPUT_DIR")
      ->capture_default_str();
  app.add_option("--lease-seconds", flags.lease_seconds,
                 "lease length in seconds; workers heartbeat every third of it")
      ->envname("TESSERA_LEASE_SECONDS")
      ->check(CLI::Range(0.1, 86400.0))
      ->capture_default_str();
  app.add_option("--port-file", flags.port_file,
                 "write the gRPC port chosen to this file once listening (for --grpc HOST:0)")
      ->envname("TESSERA_PORT_FILE");
  app.add_option("--http-port-file", flags.http_port_file,
                 "write the HTTP port chosen to this file once listening (for --http HOST:0)")
      ->envname("TESSERA_HTTP_PORT_FILE");
  CLI11_PARSE(app, argc, argv);

  // Block the stop signals before any thread starts, so only sigwait sees them.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
  try {
    return serve(flags, stop_signals);
  } catch (const std::exception& e) {
    std::cerr << "tessera-server: " << e.what() << "\n";
    return 1;
  }
}
