// tessera-server's command line: its flags (each with an environment variable), the tokens they
// resolve to, and the coordinator's configuration they make.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>
#include <vector>

#include "coordinator.h"
#include "farm_limits.h"
#include "scene/image_check.h"
#include "wire/transport_security.h"

namespace tessera::server {

struct Flags {
  std::string grpc_address = "127.0.0.1:50051";
  std::string http_address = "127.0.0.1:8080";
  std::string db = "var/tessera.db";
  std::string token, token_file;                // both services
  std::string worker_token, worker_token_file;  // WorkerService only (overrides --token there)
  std::string client_token, client_token_file;  // JobService only (overrides --token there)
  wire::ServerTls tls;
  bool insecure = false;
  std::string output_dir = "var/outputs";
  double lease_seconds = 30;
  double shutdown_seconds = 30;
  std::string port_file;
  FarmLimits limits;
  double max_bundle_mb = 512;
  WorkerHealthPolicy health;
  double forgive_seconds = 600;
  double nan_report_fraction = 1e-3;
  double retention_days = 0;  ///< --retention-days (0: keep finished jobs)
  uint64_t merge_cache_mb = 1024;  ///< --merge-cache-mb
  double check_wait_seconds = 60;  ///< --check-wait-s (spot checks' bounded wait)
  std::string http_port_file;
  std::vector<std::string> allowed_hosts;  ///< --allowed-host (repeatable)
  int http_connections_per_client = 16;    ///< --http-connections-per-client
  double http_head_timeout_s = 10;         ///< --http-head-timeout
  uint64_t submit_memory_mb = 2048;                ///< --submit-memory-mb
  uint64_t max_texture_values = kMaxImageValues;  ///< --max-texture-values
  std::string oidn_library;  ///< --oidn-library ("" = TESSERA_OIDN_LIBRARY, then the search)
};

/// Registers every flag of tessera-server on `app`, bound to `flags`.
void add_server_flags(CLI::App& app, Flags& flags);

/// The tokens each service requires, after --token, the role tokens and their files.
struct Tokens {
  std::string worker, client;
};
/// Throws std::runtime_error for a token file that cannot be read, or for equal worker and
/// client tokens given as two (one shared token is --token).
Tokens resolve_tokens(const Flags& flags);

/// The coordinator's configuration from the flags.
CoordinatorConfig coordinator_config(const Flags& flags);

}  // namespace tessera::server
