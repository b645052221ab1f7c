// A farm on loopback for end-to-end tests: tessera-server on a free port (it binds port 0 and
// writes the port it got to a file), tessera-worker processes, the tessera CLI, and gRPC stubs
// for calls the CLI does not make (simulated workers, raw bundles). Everything lives in a
// temporary folder, kept when the test fails (for its logs) and removed otherwise.
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "image/image_output.h"
#include "process.h"
#include "tessera/v1/job_service.grpc.pb.h"
#include "tessera/v1/worker_service.grpc.pb.h"
#include "wire/transport_security.h"

namespace tessera::e2e {

/// Generous bound on any wait: the tests poll state, they never time the farm.
inline constexpr std::chrono::seconds kPatience{600};
/// Deadline of each gRPC call a test makes.
inline constexpr std::chrono::seconds kCallTimeout{60};

class FarmCluster {
 public:
  explicit FarmCluster(const std::string& name);
  ~FarmCluster();

  /// Starts tessera-server with a fresh port (or the previous one after a kill) and waits
  /// until it listens. `extra` adds flags (--lease-seconds, --token).
  void start_server(const std::vector<std::string>& extra = {});
  /// SIGKILL, then wait for the process to be gone.
  void kill_server();
  /// Starts tessera-worker --server ... with its own log, `env` ("NAME=value") added to its
  /// environment; returns its index.
  size_t start_worker(const std::vector<std::string>& extra = {},
                      const std::vector<std::string>& env = {});
  Process& worker(size_t index) { return *workers_.at(index); }

  /// From now on the test's stubs connect with `tls`, and every CLI run gets `cli_flags`
  /// (--tls-ca ..., --tls-cert ...). Call before start_server.
  void use_tls(const wire::ClientTls& tls, const std::vector<std::string>& cli_flags) {
    tls_ = tls;
    cli_tls_flags_ = cli_flags;
  }
  /// From the next start_server on, the server's environment also has `env` ("NAME=value").
  void set_server_env(const std::vector<std::string>& env) { server_env_ = env; }
  /// Stops the server with `signal_number` and returns its exit code.
  std::optional<int> stop_server(int signal_number);

  /// Runs the tessera CLI against this server.
  CommandResult cli(const std::vector<std::string>& args, const std::vector<std::string>& env = {});
  /// Runs `tessera-worker render` (the local renderer).
  CommandResult local_render(const std::vector<std::string>& args);

  std::string address() const { return "127.0.0.1:" + std::to_string(port_); }
  /// The dashboard's HTTP port (the server listens on 127.0.0.1:0 for it).
  int http_port() const { return http_port_; }
  const std::filesystem::path& dir() const { return dir_; }
  /// The running server's process id (its /proc/PID/status for memory checks).
  pid_t server_pid() const { return server_->pid(); }
  std::filesystem::path db_path() const { return dir_ / "farm.db"; }

  v1::JobService::Stub& jobs() { return *jobs_; }
  v1::WorkerService::Stub& workers_api() { return *workers_api_; }
  /// A context with kCallTimeout and, when given, the bearer token.
  static std::unique_ptr<grpc::ClientContext> context(const std::string& token = "");

  v1::JobInfo job(uint64_t id);
  /// Polls the job until `done(info)` (or kPatience passes: test failure). Returns the last info.
  v1::JobInfo wait_job(uint64_t id, const std::function<bool(const v1::JobInfo&)>& done,
                       const std::string& what);
  v1::JobInfo wait_final(uint64_t id);

  /// Submits with the CLI (--json) and returns the job id.
  uint64_t submit(const std::vector<std::string>& args);

  /// Appends every process log to the test's output (called on failure).
  void dump_logs() const;

 private:
  void connect();

  std::filesystem::path dir_;
  std::string token_;
  int port_ = 0;
  int http_port_ = 0;
  int server_starts_ = 0;
  int commands_ = 0;
  std::vector<std::string> server_extra_;
  std::vector<std::string> server_env_;
  std::unique_ptr<Process> server_;
  std::vector<std::unique_ptr<Process>> workers_;
  std::unique_ptr<v1::JobService::Stub> jobs_;
  std::unique_ptr<v1::WorkerService::Stub> workers_api_;
  wire::ClientTls tls_;
  std::vector<std::string> cli_tls_flags_;
};

/// The source tree (scenes/, tests/).
std::filesystem::path source_dir();

/// Pixels of two images equal bit for bit (sizes too). On a difference, says where.
::testing::AssertionResult same_pixels(const std::filesystem::path& a, const std::filesystem::path& b);

}  // namespace tessera::e2e
