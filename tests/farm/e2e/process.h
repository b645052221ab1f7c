// A child process for end-to-end tests: started with posix_spawn, output to a log file, killed
// (SIGKILL) and reaped when the object goes away, so a failing test never leaks processes.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace tessera::e2e {

class Process {
 public:
  /// Starts argv[0] (a path) with argv[1..]; stdout and stderr go to `log` (appended). The
  /// child's environment is the test's without TESSERA_* variables, plus `env` ("NAME=value").
  Process(const std::vector<std::string>& argv, const std::filesystem::path& log,
          const std::vector<std::string>& env = {});
  /// As above with stdout and stderr in separate files.
  Process(const std::vector<std::string>& argv, const std::filesystem::path& out,
          const std::filesystem::path& err, const std::vector<std::string>& env);
  ~Process();
  Process(const Process&) = delete;
  Process& operator=(const Process&) = delete;

  pid_t pid() const { return pid_; }
  void signal(int signal_number) const;
  /// Waits for the exit up to `timeout`: the exit code, 128 + signal when killed, or nullopt
  /// when it is still running.
  std::optional<int> wait_for(std::chrono::milliseconds timeout);
  bool running();

 private:
  pid_t pid_ = -1;
  std::optional<int> status_;
};

struct CommandResult {
  int exit_code = -1;
  std::string out, err;
};

/// Runs a command to completion (killed after `timeout`), capturing stdout and stderr in
/// <stem>.out and <stem>.err.
CommandResult run_command(const std::vector<std::string>& argv, const std::filesystem::path& stem,
                          const std::vector<std::string>& env = {},
                          std::chrono::milliseconds timeout = std::chrono::minutes(10));

std::string read_text(const std::filesystem::path& path);

}  // namespace tessera::e2e
