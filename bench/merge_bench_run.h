// tessera-bench-merge (merge_throughput.cpp): one run (a server, a job, N simulated workers),
// its configuration and what it measured.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "merge_bench_util.h"

namespace tessera::bench_merge {

struct RunConfig {
  int tile = 32;
  uint32_t batch_spp = 1;
  int workers = 1;
  bool shared_channel = false;
};

struct Options {
  fs::path server_bin;
  fs::path scene;
  int size = 256;
  uint32_t units = 2048;
  double max_seconds = 30;
  uint32_t wait_ms = 1000;
  double lease_seconds = 30;
  uint32_t per_call = 1;  ///< units per LeaseUnit (max_units) and results per UploadResults
  bool keep = false;
  /// When not empty: each run writes PREFIX-N.client (every call's times as the simulated
  /// workers saw them) and the server PREFIX-N.server (its call trace), N the run's index.
  std::string trace;
};

/// One call as a simulated worker saw it (--trace): steady_clock (CLOCK_MONOTONIC) nanoseconds,
/// the clock the server's call trace reads.
struct CallRecord {
  const char* kind;
  int64_t begin_ns, end_ns;
  uint32_t units;
  std::string lease_id;  ///< the first lease of the call
};

inline int64_t ns_of(Clock::time_point t) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
}

/// What one simulated worker saw.
struct WorkerTally {
  std::vector<double> lease_ms, upload_ms;
  std::vector<CallRecord> calls;  ///< with --trace only
  uint64_t accepted = 0, dropped = 0, no_work = 0, released = 0;
  uint64_t early = 0;        ///< uploads sent before the tile's previous batch was acknowledged
  uint64_t proto_bytes = 0;  ///< protobuf payloads of the four messages of each result
  uint64_t results = 0;      ///< results uploaded (several per call with --per-call)
  Clock::time_point last_accept{};
  double last_accept_upload_ms = 0;  ///< latency of that upload
};

struct RunResult {
  RunConfig config;
  uint32_t units_total = 0;
  uint32_t per_call = 1;
  bool cut_off = false;  ///< the time bound stopped the run before the job finished
  double client_s = 0;   ///< workers released -> last accepted result
  double server_s = 0;   ///< job started_unix_ms -> finished_unix_ms
  double client_rate = 0, server_rate = 0;
  double lease_p50 = 0, lease_p99 = 0, upload_p50 = 0, upload_p99 = 0, upload_max = 0;
  /// The lease p99 without each worker's first call: every simulated worker starts at the same
  /// moment, so its first calls arrive together, N at once, and each call after them follows
  /// the worker's own last upload (BENCHMARKS.md, "Lease latency and capacity"). lease_p99
  /// counts both.
  double lease_p99_later = 0;
  double accum_bytes = 0, proto_bytes = 0;
  /// Server CPU per accepted result from the clock's start (every worker registered) to the
  /// job's end: the run's cost without the server's start-up (but with the job's submit-side
  /// share and its output at the end; tests/load/capacity.sh takes the marginal cost per
  /// result as the difference of two job sizes).
  double server_cpu_ms = 0, client_cpu_ms = 0;
  double server_cpu_life_ms = 0;  ///< server CPU from exec to the job's end, per accepted result
  double server_cpu_listen_s = 0;  ///< server CPU at listening (exec to port file), seconds
  double server_cpu_run_s = 0;     ///< server CPU from the clock's start to the job's end, seconds
  uint64_t accepted = 0;           ///< results accepted (the divisor of the per-result figures)
  double early_fraction = 0;
  double final_upload_ms = 0;  ///< the last accepted upload: it completed the job (output write)
  std::string load_before, load_after;
  std::vector<std::string> problems;
  std::vector<std::string> server_log;  ///< lines other than the start/stop lines
};

/// Runs one configuration in `dir` (a fresh server and database); `run_index` numbers its
/// --trace files. Throws BenchError when a step fails; what the checks found is in `problems`.
RunResult run_once(const Options& options, const RunConfig& config, const fs::path& dir,
                   int run_index);

}  // namespace tessera::bench_merge
