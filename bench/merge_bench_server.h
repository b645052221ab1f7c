// tessera-bench-merge (merge_throughput.cpp): a temporary folder and the tessera-server child
// process of one run, both removed or stopped by their destructors.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "merge_bench_util.h"

extern char** environ;

namespace tessera::bench_merge {

class TempDir {
 public:
  explicit TempDir(bool keep) : keep_(keep) {
    std::string pattern = (fs::temp_directory_path() / "tessera-bench-merge-XXXXXX").string();
    if (!mkdtemp(pattern.data())) {
      throw BenchError("cannot create a temporary folder under " +
                       fs::temp_directory_path().string());
    }
    path_ = pattern;
  }
  ~TempDir() {
    if (keep_) {
      std::fprintf(stderr, "kept %s\n", path_.c_str());
      return;
    }
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
  bool keep_;
};

/// tessera-server as a child process: stdout and stderr to `log`, TESSERA_* variables removed
/// from its environment (flags only). The destructor stops it (SIGTERM, then SIGKILL after 10 s)
/// and reaps it, so no run leaves a server behind.
class ServerProcess {
 public:
  /// `trace`: when not empty, the server's call trace is written there (TESSERA_CALL_TRACE,
  /// server/call_trace.h).
  ServerProcess(const fs::path& binary, const fs::path& dir, double lease_seconds,
                const std::string& trace = "")
      : log_(dir / "server.log"), trace_(trace) {
    const fs::path port_file = dir / "port";
    std::vector<std::string> args = {binary.string(),
                                     "--grpc",
                                     "127.0.0.1:0",
                                     "--http",
                                     "127.0.0.1:0",
                                     "--port-file",
                                     port_file.string(),
                                     "--db",
                                     (dir / "farm.db").string(),
                                     "--output-dir",
                                     (dir / "outputs").string(),
                                     "--lease-seconds",
                                     std::to_string(lease_seconds)};
    spawn(args);
    const auto deadline = Clock::now() + std::chrono::seconds(30);
    while (!fs::exists(port_file)) {
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        throw BenchError("tessera-server exited before listening; its log: " + log_.string() +
                         ":\n" + log_text());
      }
      if (Clock::now() > deadline) {
        throw BenchError("tessera-server did not write its port file within 30 s");
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    std::ifstream in(port_file);
    in >> port_;
    if (port_ <= 0) throw BenchError("bad port file " + port_file.string());
    // The fixed cost of a run's start (exec, dynamic linking, opening the store, gRPC set-up):
    // the server writes the port file once both listeners are up.
    cpu_at_listening_s_ = cpu_seconds(pid_);
  }

  ~ServerProcess() {
    if (pid_ <= 0) return;
    kill(pid_, SIGTERM);
    const auto deadline = Clock::now() + std::chrono::seconds(10);
    int status = 0;
    while (waitpid(pid_, &status, WNOHANG) == 0) {
      if (Clock::now() > deadline) {
        kill(pid_, SIGKILL);
        waitpid(pid_, &status, 0);
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  ServerProcess(const ServerProcess&) = delete;
  ServerProcess& operator=(const ServerProcess&) = delete;

  pid_t pid() const { return pid_; }
  /// User + system CPU seconds the server had used when its port file appeared.
  double cpu_at_listening_s() const { return cpu_at_listening_s_; }
  std::string address() const { return "127.0.0.1:" + std::to_string(port_); }
  std::string log_text() const {
    std::ifstream in(log_);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }

 private:
  void spawn(const std::vector<std::string>& args) {
    std::vector<char*> argv;
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    std::vector<char*> envp;
    for (char** e = environ; *e; ++e) {
      if (std::string_view(*e).rfind("TESSERA_", 0) != 0) envp.push_back(*e);
    }
    const std::string trace_env = "TESSERA_CALL_TRACE=" + trace_;
    if (!trace_.empty()) envp.push_back(const_cast<char*>(trace_env.c_str()));
    envp.push_back(nullptr);

    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log_.c_str(),
                                     O_WRONLY | O_CREAT | O_APPEND, 0644);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
    const int rc = posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), envp.data());
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) {
      pid_ = -1;
      throw BenchError("cannot start " + args[0] + ": " + std::strerror(rc));
    }
  }

  fs::path log_;
  std::string trace_;
  pid_t pid_ = -1;
  int port_ = 0;
  double cpu_at_listening_s_ = 0;
};

}  // namespace tessera::bench_merge
