// The `tessera` CLI's commands. Each returns the process exit code: 0 success, 1 failure (with a
// one-line reason on stderr). Usage errors (2) are CLI11's.
#pragma once

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "job/job_options.h"
#include "wire/transport_security.h"

namespace tessera::client {

struct GlobalOptions {
  std::string server = "127.0.0.1:50051";
  std::string token;
  std::string token_file;
  wire::ClientTls tls;
  double timeout_s = 30;  ///< deadline of each short call
  bool json = false;      ///< machine-readable output on stdout
};

struct SubmitOptions {
  std::string scene;
  std::string root;  ///< --root: the bundle root ("" = the scene's own, docs/mitsuba.md)
  std::vector<std::string> defines;  ///< -D name=value: Mitsuba parameters (docs/mitsuba.md)
  JobOverrides overrides;
  int priority = 0;
  bool wait = false;
  std::string output;  ///< implies wait
};

int submit(const GlobalOptions& g, const SubmitOptions& s);
int status(const GlobalOptions& g, uint64_t job_id);
int watch(const GlobalOptions& g, uint64_t job_id);
int get(const GlobalOptions& g, uint64_t job_id, const std::string& output);
int cancel(const GlobalOptions& g, uint64_t job_id);
/// delete_command.cpp: a final job off the server.
int delete_job(const GlobalOptions& g, uint64_t job_id);
int list(const GlobalOptions& g);
int workers(const GlobalOptions& g);

}  // namespace tessera::client
