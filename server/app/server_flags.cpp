#include "server_flags.h"

#include <stdexcept>

#include "cli/host_port.h"
#include "dashboard/host_check.h"
#include "wire/bearer_token.h"

namespace tessera::server {
namespace {

template <typename T>
CLI::Option* limit_option(CLI::App& app, const std::string& name, T& target, const std::string& env,
                          const std::string& help) {
  return app.add_option(name, target, help)->envname(env)->capture_default_str();
}

void add_listen_flags(CLI::App& app, Flags& flags) {
  app.add_option("--grpc", flags.grpc_address, "gRPC listen address HOST:PORT (port 0: any free)")
      ->envname("TESSERA_GRPC")
      ->check(cli::host_port_check())
      ->capture_default_str();
  app.add_option("--http", flags.http_address,
                 "HTTP dashboard, JSON API and /metrics address HOST:PORT (port 0: any free)")
      ->envname("TESSERA_HTTP")
      ->check(cli::host_port_check())
      ->capture_default_str();
  app.add_option("--db", flags.db, "SQLite database file (created if missing)")
      ->envname("TESSERA_DB")
      ->capture_default_str();
}

void add_http_flags(CLI::App& app, Flags& flags) {
  // The dashboard's HTTP front (docs/security.md, "The dashboard's HTTP front").
  app.add_option("--allowed-host", flags.allowed_hosts,
                 "a host name the dashboard's requests may name in Host and Origin besides IP "
                 "addresses, localhost and the --http host (a proxy's or ingress's name); "
                 "repeatable, or comma-separated in the variable")
      ->envname("TESSERA_ALLOWED_HOST")
      ->delimiter(',')
      ->take_all()
      ->check(CLI::Validator(
          [](std::string& name) -> std::string {
            try {
              HostCheck::normalise_name(name);
              return "";
            } catch (const std::invalid_argument& e) {
              return e.what();
            }
          },
          "NAME"));
  app.add_option("--http-connections-per-client", flags.http_connections_per_client,
                 "per client address: HTTP requests still sending their head (past it the oldest "
                 "is dropped) and requests being served (past it 503); health probes exempt")
      ->envname("TESSERA_HTTP_CONNECTIONS_PER_CLIENT")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  app.add_option("--http-head-timeout", flags.http_head_timeout_s,
                 "seconds an HTTP client has from connecting to the end of its request's head "
                 "(TLS handshake included); a body gets as long again")
      ->envname("TESSERA_HTTP_HEAD_TIMEOUT")
      ->check(CLI::Range(0.1, 3600.0))
      ->capture_default_str();
}

void add_security_flags(CLI::App& app, Flags& flags) {
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
}

void add_run_flags(CLI::App& app, Flags& flags) {
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
}

void add_limit_flags(CLI::App& app, Flags& flags) {
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
  limit_option(app, "--max-unit-samples", limits.max_unit_samples, "TESSERA_MAX_UNIT_SAMPLES",
               "most samples in one work unit (tile pixels x the batch's samples per pixel); a "
               "worker stopping finishes its unit first, so this bounds how long that takes")
      ->check(CLI::Range(uint64_t(1), uint64_t(1) << 40));
  limit_option(app, "--max-pixels", limits.max_pixels_per_job, "TESSERA_MAX_PIXELS",
               "most pixels (width x height) per job; the server holds a job's whole image when "
               "it writes it, about 70 bytes a pixel")
      ->check(CLI::Range(uint64_t(1), uint64_t(32768) * 32768));
}

void add_health_flags(CLI::App& app, Flags& flags) {
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
}

void add_store_flags(CLI::App& app, Flags& flags) {
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
  app.add_option("--check-wait-s", flags.check_wait_seconds,
                 "a result held for a spot check merges unchecked (counted unverified) when no"
                 " other worker delivered the check within this many seconds")
      ->envname("TESSERA_CHECK_WAIT_S")
      ->check(CLI::Range(0.0, 86400.0))
      ->capture_default_str();
  app.add_option("--http-port-file", flags.http_port_file,
                 "write the HTTP port chosen to this file once listening (for --http HOST:0)")
      ->envname("TESSERA_HTTP_PORT_FILE");
}

void add_submit_flags(CLI::App& app, Flags& flags) {
  // The checks of submitted bundles (docs/farm.md, "The server's memory").
  limit_option(app, "--submit-memory-mb", flags.submit_memory_mb, "TESSERA_SUBMIT_MEMORY_MB",
               "memory for checking submitted bundles, all submits together, MiB: each reserves "
               "three times its bytes plus what decoding its meshes and images takes (from their "
               "headers) before it is checked; a bundle needing more is refused, submits that do "
               "not fit beside the others wait up to 60 s, then get RESOURCE_EXHAUSTED")
      ->check(CLI::Range(uint64_t(16), uint64_t(1) << 20));
  limit_option(app, "--max-texture-values", flags.max_texture_values,
               "TESSERA_MAX_TEXTURE_VALUES",
               "most values (width x height x channels) of one image file of a bundle (textures, "
               "environment maps); the default, a 16384 x 8192 RGBA map, is also the local CLI's "
               "limit and the most this flag allows")
      ->check(CLI::Range(uint64_t(1), kMaxImageValues));
  app.add_option("--oidn-library", flags.oidn_library,
                 "libOpenImageDenoise.so.2 for jobs submitted with --denoise (default: "
                 "TESSERA_OIDN_LIBRARY, else the one found at build time, else the system's); "
                 "without it such jobs are refused");
}

}  // namespace

void add_server_flags(CLI::App& app, Flags& flags) {
  // In this order in --help.
  add_listen_flags(app, flags);
  add_http_flags(app, flags);
  add_security_flags(app, flags);
  add_run_flags(app, flags);
  add_limit_flags(app, flags);
  add_health_flags(app, flags);
  add_store_flags(app, flags);
  add_submit_flags(app, flags);
}

Tokens resolve_tokens(const Flags& flags) {
  namespace tw = wire;
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

CoordinatorConfig coordinator_config(const Flags& flags) {
  CoordinatorConfig config;
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
  config.check_wait_ms = int64_t(flags.check_wait_seconds * 1000.0);
  return config;
}

}  // namespace tessera::server
