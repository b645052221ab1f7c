// tessera-bench-merge: the server's merge throughput: how many results per second a real
// tessera-server accepts and merges when N simulated workers lease units and upload results as
// fast as it answers.
//
// Per run: a fresh tessera-server child process on 127.0.0.1 (port 0, --port-file) with its own
// temporary SQLite database; one job submitted through JobService (the scene bundle of
// scenes/cornell.json, 256x256, many small units); N threads speaking the worker protocol over
// real gRPC (Register once, then LeaseUnit -> UploadResult until the job ends). Nothing renders:
// every result is an encoded Accumulation precomputed before the clock starts (one per tile
// rectangle — the codec writes the rectangle into the bytes — with plausible noisy float-valued
// sums), so the figure is the server's: gRPC, decode, SQLite transaction, in-order merge,
// re-encode of the tile, the job's output at the end.
//
// After each run the job must be DONE with results_merged == units_done == units_total,
// results_dropped == leases_expired == units_released == 0, and every unit acknowledged exactly
// once on the client side: the benchmark also shows that nothing is lost under load. Any
// violation is printed and makes the exit status 1.
//
//   tessera-bench-merge                                  # tiles 16,32,64 x workers 1,4,16,64
//   tessera-bench-merge --tiles 32 --workers 16 --reps 5 --channel shared
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <latch>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "accum/accumulation.h"
#include "accum/accumulation_codec.h"
#include "job/job_plan.h"
#include "tessera/v1/job_service.grpc.pb.h"
#include "tessera/v1/worker_service.grpc.pb.h"
#include "wire/rpc_channel.h"
#include "wire/scene_bundle.h"

extern char** environ;

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using namespace tessera;

namespace {

// ---------------------------------------------------------------------------------------------
// Errors and small helpers

/// A failed benchmark step (server would not start, an RPC failed): what() is one line.
class BenchError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

double seconds_between(Clock::time_point t0, Clock::time_point t1) {
  return std::chrono::duration<double>(t1 - t0).count();
}

double ms_between(Clock::time_point t0, Clock::time_point t1) {
  return std::chrono::duration<double, std::milli>(t1 - t0).count();
}

std::string load_average() {
  std::ifstream in("/proc/loadavg");
  std::string one, five, fifteen;
  in >> one >> five >> fifteen;
  return one + " " + five + " " + fifteen;
}

/// User + system CPU seconds of process `pid` (from /proc/PID/stat), or of this process when
/// pid is 0.
double cpu_seconds(pid_t pid) {
  if (pid == 0) {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    auto tv = [](const timeval& t) { return double(t.tv_sec) + double(t.tv_usec) * 1e-6; };
    return tv(usage.ru_utime) + tv(usage.ru_stime);
  }
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  std::getline(in, line);
  const size_t close = line.rfind(')');  // the command name may contain spaces
  if (close == std::string::npos) return 0;
  std::istringstream fields(line.substr(close + 2));
  std::string field;
  // After "pid (comm) ": state is field 3; utime and stime are fields 14 and 15.
  for (int i = 3; i <= 13; ++i) fields >> field;
  double utime = 0, stime = 0;
  fields >> utime >> stime;
  return (utime + stime) / double(sysconf(_SC_CLK_TCK));
}

/// Nearest-rank percentile of `values` (sorted in place); 0 when empty.
double percentile(std::vector<double>& values, double p) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const size_t rank = size_t(std::ceil(p / 100.0 * double(values.size())));
  return values[std::clamp<size_t>(rank, 1, values.size()) - 1];
}

double median(std::vector<double> values) { return percentile(values, 50); }

// ---------------------------------------------------------------------------------------------
// RAII: a temporary folder and the server child process

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

// ---------------------------------------------------------------------------------------------
// Channels and calls

/// The farm's channel settings (wire::make_channel's), plus a local subchannel pool when each
/// simulated worker must have its own TCP connection as separate worker processes would:
/// otherwise gRPC shares one connection between channels with equal arguments.
std::shared_ptr<grpc::Channel> make_channel(const std::string& address, bool own_connection) {
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(wire::kMaxMessageBytes);
  args.SetMaxSendMessageSize(wire::kMaxMessageBytes);
  args.SetInt(GRPC_ARG_KEEPALIVE_TIME_MS, wire::kKeepaliveTimeMs);
  args.SetInt(GRPC_ARG_KEEPALIVE_TIMEOUT_MS, wire::kKeepaliveTimeoutMs);
  args.SetInt(GRPC_ARG_KEEPALIVE_PERMIT_WITHOUT_CALLS, 1);
  if (own_connection) args.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);
  return grpc::CreateCustomChannel(address, grpc::InsecureChannelCredentials(), args);
}

void check_status(const grpc::Status& status, const std::string& call) {
  if (!status.ok()) throw BenchError(call + " failed: " + wire::status_line(status));
}

/// Deadlines: the worker's own (docs/farm.md, "gRPC"), except uploads (120 s there): a run is
/// bounded, so an upload that takes 60 s is already a failure worth reporting.
constexpr auto kCallTimeout = std::chrono::seconds(10);
constexpr auto kUploadTimeout = std::chrono::seconds(60);

// ---------------------------------------------------------------------------------------------
// Precomputed results

/// A plausible result of `samples` samples per pixel over `rect`: per pixel, float radiance
/// samples (a smooth image times exponential noise, a rare firefly) summed in double, their
/// squared luminance, and the count — what a worker's render gives, with the same spread of
/// mantissa bits, so the codec's compression ratio is realistic.
Accumulation noisy_accumulation(const TileRect& rect, uint32_t samples, uint64_t seed) {
  Accumulation acc(rect);
  std::mt19937_64 rng(seed);
  std::exponential_distribution<float> noise(1.0f);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  size_t i = 0;
  for (int y = rect.y0; y < rect.y1; ++y) {
    for (int x = rect.x0; x < rect.x1; ++x, ++i) {
      const float base[3] = {0.5f + 0.3f * std::sin(float(x) * 0.05f),
                             0.4f + 0.2f * std::cos(float(y) * 0.07f), 0.3f};
      for (uint32_t s = 0; s < samples; ++s) {
        const float scale = noise(rng) * (u01(rng) < 0.01f ? 40.0f : 1.0f);
        float rgb[3];
        for (int c = 0; c < 3; ++c) rgb[c] = base[c] * scale;
        for (int c = 0; c < 3; ++c) acc.rgb[3 * i + size_t(c)] += double(rgb[c]);
        const double y_lum = luminance(rgb[0], rgb[1], rgb[2]);
        acc.lum2[i] += y_lum * y_lum;
      }
      acc.count[i] = samples;
    }
  }
  return acc;
}

/// The encoded result of every (tile, samples-per-pixel) the job's units can ask for.
class ResultBank {
 public:
  explicit ResultBank(const JobPlan& plan) {
    const std::vector<TileRect> tiles = plan.tiles();
    for (uint32_t b = 0; b < plan.batch_count(); ++b) {
      const uint32_t samples = plan.batch_end(b) - plan.batch_begin(b);
      for (size_t t = 0; t < tiles.size(); ++t) {
        const auto key = std::make_pair(uint32_t(t), samples);
        if (!bytes_.contains(key)) {
          bytes_[key] =
              encode_accumulation(noisy_accumulation(tiles[t], samples, t * 7919 + samples));
        }
      }
    }
  }
  /// Throws BenchError for a unit the plan does not have.
  const std::string& get(uint32_t tile, uint32_t samples) const {
    const auto it = bytes_.find({tile, samples});
    if (it == bytes_.end()) {
      throw BenchError("no precomputed result for tile " + std::to_string(tile) + " with " +
                       std::to_string(samples) + " spp");
    }
    return it->second;
  }
  double mean_bytes() const {
    double sum = 0;
    for (const auto& [key, bytes] : bytes_) sum += double(bytes.size());
    return bytes_.empty() ? 0 : sum / double(bytes_.size());
  }

 private:
  std::map<std::pair<uint32_t, uint32_t>, std::string> bytes_;
};

// ---------------------------------------------------------------------------------------------
// One run

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

int64_t ns_of(Clock::time_point t) {
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

/// State shared by the simulated workers of one run.
struct RunShared {
  uint64_t job_id = 0;
  uint32_t batch_count = 0;
  std::vector<std::atomic<uint8_t>> acked;  ///< per unit (tile * batches + batch): times accepted
  std::atomic<bool> job_ended{false};
  std::atomic<bool> stop{false};  ///< time bound reached or a worker failed
  std::mutex error_mu;
  std::string error;  ///< first failure (guarded by error_mu)

  explicit RunShared(size_t units) : acked(units) {}
  void fail(const std::string& what) {
    {
      std::lock_guard lock(error_mu);
      if (error.empty()) error = what;
    }
    stop = true;
  }
};

/// One simulated worker: Register, then LeaseUnit -> UploadResult until the job ends (or the
/// run is stopped, when a held unit is handed back with ReleaseUnit SHUTDOWN).
void simulated_worker(int index, std::shared_ptr<grpc::Channel> channel, const Options& options,
                      const ResultBank& bank, RunShared& shared, std::latch& registered,
                      std::latch& go, WorkerTally& tally) {
  auto stub = v1::WorkerService::NewStub(channel);
  bool counted = false;  // a latch must not be counted down twice
  try {
    v1::RegisterRequest reg;
    reg.set_name("bench-" + std::to_string(index));
    reg.set_threads(1);
    reg.set_isa("bench");
    reg.set_version("bench");
    v1::RegisterResponse reg_reply;
    {
      grpc::ClientContext ctx;
      wire::prepare_context(ctx, "", kCallTimeout);
      // Before the clock: N channels connecting at once sometimes saw a connection attempt fail
      // ("failed to connect to all addresses", and the run was lost); wait for the channel
      // instead, within the call's deadline.
      ctx.set_wait_for_ready(true);
      check_status(stub->Register(&ctx, reg, &reg_reply), "Register");
    }
    registered.count_down();
    counted = true;
    go.wait();
    const bool batched = options.per_call > 1;
    while (!shared.stop) {
      v1::LeaseUnitRequest lease_req;
      lease_req.set_worker_id(reg_reply.worker_id());
      lease_req.set_wait_ms(options.wait_ms);
      if (batched) lease_req.set_max_units(options.per_call);
      v1::LeaseUnitResponse lease;
      const auto t0 = Clock::now();
      {
        grpc::ClientContext ctx;
        wire::prepare_context(ctx, "", kCallTimeout + std::chrono::milliseconds(options.wait_ms));
        check_status(stub->LeaseUnit(&ctx, lease_req, &lease), "LeaseUnit");
      }
      const auto t1 = Clock::now();
      if (!lease.leased()) {
        ++tally.no_work;
        if (shared.job_ended) break;
        continue;
      }
      tally.lease_ms.push_back(ms_between(t0, t1));
      // The leases of this call: one in the single-unit fields, or several in `leases`.
      std::vector<std::pair<std::string, v1::WorkUnit>> held;
      if (batched) {
        for (const v1::UnitLease& l : lease.leases()) held.emplace_back(l.lease_id(), l.unit());
      } else {
        held.emplace_back(lease.lease_id(), lease.unit());
      }
      if (!options.trace.empty() && !held.empty()) {
        tally.calls.push_back({"lease", ns_of(t0), ns_of(t1), uint32_t(held.size()),
                               held.front().first});
      }
      if (shared.stop) {  // bounded run: hand the units back rather than leave leases behind
        for (const auto& [lease_id, unit] : held) {
          v1::ReleaseUnitRequest release;
          release.set_worker_id(reg_reply.worker_id());
          release.set_lease_id(lease_id);
          release.set_reason(v1::ReleaseUnitRequest::REASON_SHUTDOWN);
          v1::ReleaseUnitResponse released;
          grpc::ClientContext ctx;
          wire::prepare_context(ctx, "", kCallTimeout);
          check_status(stub->ReleaseUnit(&ctx, release, &released), "ReleaseUnit");
          ++tally.released;
        }
        break;
      }
      v1::UploadResultsRequest uploads;
      uploads.set_worker_id(reg_reply.worker_id());
      std::vector<size_t> slots;
      for (const auto& [lease_id, unit] : held) {
        v1::UploadResultRequest* upload = uploads.add_results();
        upload->set_worker_id(reg_reply.worker_id());
        upload->set_lease_id(lease_id);
        upload->set_job_id(unit.job_id());
        upload->set_tile(unit.tile());
        upload->set_batch(unit.batch());
        upload->set_accumulation(bank.get(unit.tile(), unit.sample_end() - unit.sample_begin()));
        upload->set_isa("bench");
        upload->set_render_ms(0);
        const size_t slot = size_t(unit.tile()) * shared.batch_count + unit.batch();
        if (slot >= shared.acked.size()) {
          throw BenchError("leased unit tile " + std::to_string(unit.tile()) + " batch " +
                           std::to_string(unit.batch()) + " is outside the job's plan");
        }
        if (unit.batch() > 0 && shared.acked[slot - 1] == 0) ++tally.early;
        slots.push_back(slot);
      }
      v1::UploadResultsResponse results;
      const auto t2 = Clock::now();
      if (batched) {
        grpc::ClientContext ctx;
        wire::prepare_context(ctx, "", kUploadTimeout);
        check_status(stub->UploadResults(&ctx, uploads, &results), "UploadResults");
      } else {
        grpc::ClientContext ctx;
        wire::prepare_context(ctx, "", kUploadTimeout);
        check_status(stub->UploadResult(&ctx, uploads.results(0), results.add_results()),
                     "UploadResult");
      }
      const auto t3 = Clock::now();
      if (results.results_size() != int(slots.size())) {
        throw BenchError("UploadResults answered " + std::to_string(results.results_size()) +
                         " results for " + std::to_string(slots.size()));
      }
      tally.upload_ms.push_back(ms_between(t2, t3));
      if (!options.trace.empty()) {
        tally.calls.push_back({"upload", ns_of(t2), ns_of(t3), uint32_t(slots.size()),
                               held.front().first});
      }
      tally.proto_bytes += lease_req.ByteSizeLong() + lease.ByteSizeLong() +
                           (batched ? uploads.ByteSizeLong() + results.ByteSizeLong()
                                    : uploads.results(0).ByteSizeLong() +
                                          results.results(0).ByteSizeLong());
      tally.results += slots.size();
      for (size_t i = 0; i < slots.size(); ++i) {
        if (results.results(int(i)).accepted()) {
          ++tally.accepted;
          tally.last_accept = t3;
          tally.last_accept_upload_ms = tally.upload_ms.back();
          if (shared.acked[slots[i]].fetch_add(1) != 0) {
            throw BenchError("unit " + std::to_string(slots[i]) + " was accepted twice");
          }
        } else {
          ++tally.dropped;
        }
      }
    }
  } catch (const std::exception& e) {
    shared.fail("worker " + std::to_string(index) + ": " + e.what());
    if (!counted) registered.count_down();
  }
}

v1::JobInfo get_job(v1::JobService::Stub& jobs, uint64_t job_id) {
  v1::GetJobRequest request;
  request.set_job_id(job_id);
  v1::JobInfo info;
  grpc::ClientContext ctx;
  wire::prepare_context(ctx, "", kCallTimeout);
  check_status(jobs.GetJob(&ctx, request, &info), "GetJob");
  return info;
}

bool is_final(v1::JobState state) {
  return state == v1::JOB_STATE_DONE || state == v1::JOB_STATE_FAILED ||
         state == v1::JOB_STATE_CANCELLED;
}

/// The job's size: `units` (rounded up to whole batches per tile) of batch_spp samples.
JobPlan plan_for(const Options& options, const RunConfig& config) {
  JobPlan probe =
      make_job_plan(options.size, options.size, config.tile, config.batch_spp, config.batch_spp);
  const uint32_t tiles = uint32_t(probe.tile_count());
  const uint32_t batches = std::max<uint32_t>(1, (options.units + tiles - 1) / tiles);
  return make_job_plan(options.size, options.size, config.tile, batches * config.batch_spp,
                       config.batch_spp);
}

uint64_t submit_job(v1::JobService::Stub& jobs, const Options& options, const JobPlan& plan) {
  v1::SubmitJobRequest request;
  *request.mutable_bundle() = wire::bundle_to_proto(wire::bundle_from_disk(options.scene));
  v1::JobRequestOptions* o = request.mutable_options();
  o->set_width(plan.width);
  o->set_height(plan.height);
  o->set_spp(plan.spp);
  o->set_tile_size(plan.tile_size);
  o->set_batch_spp(plan.batch_spp);
  v1::SubmitJobResponse reply;
  grpc::ClientContext ctx;
  wire::prepare_context(ctx, "", std::chrono::seconds(60));
  check_status(jobs.SubmitJob(&ctx, request, &reply), "SubmitJob");
  const v1::JobInfo& job = reply.job();
  if (job.counters().units_total() != uint32_t(plan.tile_count()) * plan.batch_count()) {
    throw BenchError("the server planned " + std::to_string(job.counters().units_total()) +
                     " units; expected " +
                     std::to_string(uint32_t(plan.tile_count()) * plan.batch_count()));
  }
  return job.id();
}

/// The checks that prove nothing was lost or merged twice.
void check_final(const v1::JobInfo& job, const RunShared& shared, uint64_t accepted,
                 uint64_t dropped, RunResult& r) {
  const v1::JobCounters& c = job.counters();
  auto expect = [&](bool ok, const std::string& what) {
    if (!ok) r.problems.push_back(what);
  };
  const std::string counts = " (units_total " + std::to_string(c.units_total()) + ", units_done " +
                             std::to_string(c.units_done()) + ", results_merged " +
                             std::to_string(c.results_merged()) + ", client accepted " +
                             std::to_string(accepted) + ")";
  expect(c.results_dropped() == 0 && dropped == 0, "results dropped: server " +
                                                       std::to_string(c.results_dropped()) +
                                                       ", client " + std::to_string(dropped));
  expect(c.leases_expired() == 0, "leases expired: " + std::to_string(c.leases_expired()));
  expect(c.units_done() == accepted, "server units_done != client accepted" + counts);
  if (!r.cut_off) {
    expect(job.state() == v1::JOB_STATE_DONE,
           "job ended " + v1::JobState_Name(job.state()) + " " + job.error());
    expect(c.units_released() == 0, "units released: " + std::to_string(c.units_released()));
    expect(c.units_done() == c.units_total() && c.results_merged() == c.units_total(),
           "not every unit merged exactly once" + counts);
    size_t once = 0;
    for (const auto& a : shared.acked) once += (a == 1);
    expect(once == shared.acked.size(), "client saw " + std::to_string(once) + " of " +
                                            std::to_string(shared.acked.size()) +
                                            " units accepted exactly once");
  } else {
    expect(c.results_merged() <= c.units_done(), "more results merged than accepted" + counts);
  }
}

/// The simulated workers' threads. join() (or the destructor, when a step of the run threw)
/// ends the run — releases workers still waiting to start, tells them the job ended — and joins
/// every thread, so no thread outlives the state it uses.
class WorkerThreads {
 public:
  WorkerThreads(RunShared& shared, std::latch& go) : shared_(shared), go_(go) {}
  ~WorkerThreads() {
    shared_.stop = true;
    join();
  }
  WorkerThreads(const WorkerThreads&) = delete;
  WorkerThreads& operator=(const WorkerThreads&) = delete;

  void add(std::thread thread) { threads_.push_back(std::move(thread)); }
  void go() {
    if (!released_) go_.count_down();
    released_ = true;
  }
  void join() {
    go();
    shared_.job_ended = true;
    for (std::thread& t : threads_) {
      if (t.joinable()) t.join();
    }
  }

 private:
  RunShared& shared_;
  std::latch& go_;
  std::vector<std::thread> threads_;
  bool released_ = false;
};

RunResult run_once(const Options& options, const RunConfig& config, const fs::path& dir,
                   int run_index) {
  RunResult r;
  r.config = config;
  fs::create_directories(dir);
  const JobPlan plan = plan_for(options, config);
  const ResultBank bank(plan);  // before the clock: the benchmark measures the server

  const std::string trace_prefix =
      options.trace.empty() ? "" : options.trace + "-" + std::to_string(run_index);
  ServerProcess server(options.server_bin, dir, options.lease_seconds,
                       trace_prefix.empty() ? "" : trace_prefix + ".server");
  auto control = make_channel(server.address(), true);
  auto jobs = v1::JobService::NewStub(control);
  const uint64_t job_id = submit_job(*jobs, options, plan);
  r.units_total = uint32_t(plan.tile_count()) * plan.batch_count();
  r.per_call = options.per_call;

  RunShared shared(r.units_total);
  shared.job_id = job_id;
  shared.batch_count = plan.batch_count();
  std::vector<WorkerTally> tallies(size_t(config.workers));
  std::latch registered(config.workers), go(1);
  WorkerThreads threads(shared, go);
  {
    auto shared_channel = make_channel(server.address(), true);
    for (int i = 0; i < config.workers; ++i) {
      auto channel = config.shared_channel ? shared_channel : make_channel(server.address(), true);
      threads.add(std::thread(simulated_worker, i, channel, std::cref(options), std::cref(bank),
                              std::ref(shared), std::ref(registered), std::ref(go),
                              std::ref(tallies[size_t(i)])));
    }
  }
  registered.wait();  // every worker registered and connected: the clock starts now
  r.load_before = load_average();
  const double server_cpu0 = cpu_seconds(server.pid()), client_cpu0 = cpu_seconds(0);
  const auto start = Clock::now();
  const auto deadline = start + std::chrono::duration<double>(options.max_seconds);
  threads.go();

  v1::JobInfo job;
  try {
    for (;;) {
      job = get_job(*jobs, job_id);
      if (is_final(job.state()) || shared.stop) break;
      if (Clock::now() > deadline) {
        r.cut_off = true;
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  } catch (const std::exception& e) {
    shared.fail(std::string("monitor: ") + e.what());
  }
  if (r.cut_off) shared.stop = true;
  threads.join();
  const int64_t stopped_unix_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                                      std::chrono::system_clock::now().time_since_epoch())
                                      .count();
  const double server_cpu1 = cpu_seconds(server.pid()), client_cpu1 = cpu_seconds(0);
  r.load_after = load_average();
  if (!shared.error.empty()) throw BenchError(shared.error);
  job = get_job(*jobs, job_id);

  // Figures.
  std::vector<double> lease_ms, upload_ms, later_lease_ms;
  uint64_t accepted = 0, dropped = 0, early = 0, proto_bytes = 0, results = 0;
  Clock::time_point last = start;
  for (const WorkerTally& t : tallies) {
    lease_ms.insert(lease_ms.end(), t.lease_ms.begin(), t.lease_ms.end());
    if (t.lease_ms.size() > 1) {
      later_lease_ms.insert(later_lease_ms.end(), t.lease_ms.begin() + 1, t.lease_ms.end());
    }
    upload_ms.insert(upload_ms.end(), t.upload_ms.begin(), t.upload_ms.end());
    accepted += t.accepted;
    dropped += t.dropped;
    early += t.early;
    proto_bytes += t.proto_bytes;
    results += t.results;
    if (t.accepted > 0 && t.last_accept >= last) {
      last = t.last_accept;
      r.final_upload_ms = t.last_accept_upload_ms;
    }
  }
  r.client_s = seconds_between(start, last);
  r.client_rate = r.client_s > 0 ? double(accepted) / r.client_s : 0;
  // A cut-off job has no finish time: its interval ends when the last worker stopped.
  const int64_t end_unix_ms = r.cut_off ? stopped_unix_ms : job.finished_unix_ms();
  if (job.started_unix_ms() > 0 && end_unix_ms > job.started_unix_ms()) {
    r.server_s = double(end_unix_ms - job.started_unix_ms()) / 1000.0;
    r.server_rate = double(job.counters().results_merged()) / r.server_s;
  }
  r.lease_p50 = percentile(lease_ms, 50);
  r.lease_p99 = percentile(lease_ms, 99);
  r.lease_p99_later = percentile(later_lease_ms, 99);
  r.upload_p50 = percentile(upload_ms, 50);
  r.upload_p99 = percentile(upload_ms, 99);
  r.upload_max = upload_ms.empty() ? 0 : *std::max_element(upload_ms.begin(), upload_ms.end());
  r.accum_bytes = bank.mean_bytes();
  r.proto_bytes = results ? double(proto_bytes) / double(results) : 0;
  r.accepted = accepted;
  r.server_cpu_listen_s = server.cpu_at_listening_s();
  r.server_cpu_run_s = server_cpu1 - server_cpu0;
  r.server_cpu_ms = accepted ? (server_cpu1 - server_cpu0) * 1000.0 / double(accepted) : 0;
  r.server_cpu_life_ms = accepted ? server_cpu1 * 1000.0 / double(accepted) : 0;
  r.client_cpu_ms = accepted ? (client_cpu1 - client_cpu0) * 1000.0 / double(accepted) : 0;
  r.early_fraction = results ? double(early) / double(results) : 0;
  check_final(job, shared, accepted, dropped, r);
  if (!trace_prefix.empty()) {
    std::ofstream out(trace_prefix + ".client");
    for (size_t w = 0; w < tallies.size(); ++w) {
      for (const CallRecord& c : tallies[w].calls) {
        out << c.kind << ' ' << w << ' ' << c.begin_ns << ' ' << c.end_ns << ' ' << c.units << ' '
            << c.lease_id << '\n';
      }
    }
  }

  std::istringstream log(server.log_text());
  for (std::string line; std::getline(log, line);) {
    if (line.find("listening on") == std::string::npos &&
        line.find("shutting down") == std::string::npos) {
      r.server_log.push_back(line);
    }
  }
  return r;
}

// ---------------------------------------------------------------------------------------------
// Output

std::string config_name(const RunConfig& c) {
  char text[64];
  std::snprintf(text, sizeof text, "%2d %d %3d %-6s", c.tile, c.batch_spp, c.workers,
                c.shared_channel ? "shared" : "own");
  return text;
}

void print_header() {
  std::printf(
      "tile b   N chan   | units  res/s(client) merged/s(server) | lease p50/p99 ms | upload "
      "p50/p99/max ms | accum B  proto B/res | srv CPU ms/res cli CPU ms/res | srv CPU s listen, "
      "ms/res life | early%% | ok\n");
}

void print_row(const RunResult& r, const char* label) {
  std::printf(
      "%s | %5u %10.0f %12.0f      | %6.2f %7.2f   | %6.2f %7.2f %7.1f  | %7.0f %9.0f  | %8.2f "
      "%12.2f      | %8.3f %8.2f         | %5.1f | %s%s\n",
      config_name(r.config).c_str(), r.units_total, r.client_rate, r.server_rate, r.lease_p50,
      r.lease_p99, r.upload_p50, r.upload_p99, r.upload_max, r.accum_bytes, r.proto_bytes,
      r.server_cpu_ms, r.client_cpu_ms, r.server_cpu_listen_s, r.server_cpu_life_ms,
      100.0 * r.early_fraction, r.problems.empty() ? "yes" : "NO", r.cut_off ? " (cut off)" : "");
  if (label[0]) {
    std::printf("    %s\n", label);
    // One line per run for scripts (tests/load/capacity.sh): key=value, no spaces in values.
    std::printf(
        "    run: tile=%d workers=%d per_call=%u units=%u accepted=%llu merged_per_s=%.1f "
        "lease_p99_ms=%.2f lease_p99_later_ms=%.2f cpu_listen_s=%.4f cpu_run_s=%.4f "
        "cpu_life_ms_per_res=%.4f cpu_run_ms_per_res=%.4f checks=%s cut_off=%d\n",
        r.config.tile, r.config.workers, r.per_call, r.units_total,
        static_cast<unsigned long long>(r.accepted), r.server_rate, r.lease_p99, r.lease_p99_later,
        r.server_cpu_listen_s, r.server_cpu_run_s, r.server_cpu_life_ms, r.server_cpu_ms,
        r.problems.empty() ? "passed" : "FAILED", r.cut_off ? 1 : 0);
  }
  std::fflush(stdout);
}

/// The median of each figure over repetitions of one configuration.
RunResult median_of(const std::vector<RunResult>& runs) {
  RunResult m = runs.front();
  auto med = [&](double RunResult::*field) {
    std::vector<double> v;
    for (const RunResult& r : runs) v.push_back(r.*field);
    m.*field = median(v);
  };
  for (double RunResult::*f :
       {&RunResult::client_rate, &RunResult::server_rate, &RunResult::lease_p50,
        &RunResult::lease_p99, &RunResult::lease_p99_later, &RunResult::upload_p50, &RunResult::upload_p99,
        &RunResult::upload_max, &RunResult::accum_bytes, &RunResult::proto_bytes,
        &RunResult::server_cpu_ms, &RunResult::client_cpu_ms, &RunResult::early_fraction,
        &RunResult::server_cpu_life_ms, &RunResult::server_cpu_listen_s,
        &RunResult::server_cpu_run_s}) {
    med(f);
  }
  m.cut_off = false;
  m.problems.clear();
  for (const RunResult& r : runs) {
    m.cut_off = m.cut_off || r.cut_off;
    m.problems.insert(m.problems.end(), r.problems.begin(), r.problems.end());
  }
  return m;
}

template <typename T>
std::vector<T> parse_list(const std::string& text, const char* flag) {
  std::vector<T> values;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    try {
      const long v = std::stol(item);
      if (v < 1) throw std::out_of_range("");
      values.push_back(T(v));
    } catch (const std::exception&) {
      throw BenchError(std::string(flag) +
                       ": expected positive integers separated by commas (got \"" + text + "\")");
    }
  }
  if (values.empty()) throw BenchError(std::string(flag) + ": empty list");
  return values;
}

fs::path default_server_bin() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path("tessera-server") : self.parent_path() / "tessera-server";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "The server's merge throughput: a real tessera-server, N simulated workers over gRPC "
      "uploading precomputed results"};
  Options options;
  options.server_bin = default_server_bin();
  options.scene = fs::path(TESSERA_SOURCE_DIR) / "scenes" / "cornell.json";
  std::string tiles_text = "16,32,64", batches_text = "1", workers_text = "1,4,16,64";
  std::string channel = "own";
  int reps = 1;
  app.add_option("--server-bin", options.server_bin, "tessera-server binary")
      ->capture_default_str();
  app.add_option("--scene", options.scene, "scene file submitted (bundled with what it references)")
      ->capture_default_str();
  app.add_option("--size", options.size, "image width and height, pixels")
      ->check(CLI::Range(16, 4096))
      ->capture_default_str();
  app.add_option("--tiles", tiles_text, "tile sizes, comma-separated")->capture_default_str();
  app.add_option("--batch", batches_text, "batch sizes (spp per unit), comma-separated")
      ->capture_default_str();
  app.add_option("--workers", workers_text, "simulated worker counts, comma-separated")
      ->capture_default_str();
  app.add_option("--channel", channel,
                 "own: one channel (TCP connection) per simulated worker; shared: one for all")
      ->check(CLI::IsMember({"own", "shared"}))
      ->capture_default_str();
  app.add_option("--units", options.units, "units per job (rounded up to whole batches per tile)")
      ->check(CLI::Range(1u, 1u << 20))
      ->capture_default_str();
  app.add_option("--max-seconds", options.max_seconds,
                 "bound on each run; a job not finished by then is cut off (workers stop)")
      ->check(CLI::Range(1.0, 600.0))
      ->capture_default_str();
  app.add_option("--wait-ms", options.wait_ms, "LeaseUnit long-poll wait when there is no work")
      ->check(CLI::Range(0u, 5000u))
      ->capture_default_str();
  app.add_option("--lease-seconds", options.lease_seconds, "the server's --lease-seconds")
      ->capture_default_str();
  app.add_option("--per-call", options.per_call,
                 "units leased per LeaseUnit call (max_units) and results per UploadResults call;"
                 " 1: LeaseUnit and UploadResult as workers before batched calls")
      ->check(CLI::Range(1u, 64u))
      ->capture_default_str();
  app.add_option("--reps", reps, "repetitions of each configuration (medians printed)")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  app.add_flag("--keep", options.keep, "keep the temporary folder (databases, server logs)");
  app.add_option("--trace", options.trace,
                 "PREFIX: write every call's times, the workers' to PREFIX-N.client and the "
                 "server's (TESSERA_CALL_TRACE) to PREFIX-N.server, N the run's index");
  CLI11_PARSE(app, argc, argv);

  try {
    if (!fs::exists(options.server_bin)) {
      throw BenchError("no server binary at " + options.server_bin.string() +
                       " (build tessera-server or pass --server-bin)");
    }
    const auto tiles = parse_list<int>(tiles_text, "--tiles");
    const auto batches = parse_list<uint32_t>(batches_text, "--batch");
    const auto workers = parse_list<int>(workers_text, "--workers");
    TempDir temp(options.keep);
    std::printf(
        "tessera-bench-merge: %dx%d, ~%u units per job, %u unit(s) per call, %d rep(s), server "
        "%s\n",
        options.size, options.size, options.units, options.per_call, reps,
        options.server_bin.c_str());
    std::printf("load average at start: %s (%u CPUs)\n", load_average().c_str(),
                std::thread::hardware_concurrency());
    print_header();

    std::vector<RunResult> medians;
    int run_index = 0;
    for (int tile : tiles) {
      for (uint32_t batch : batches) {
        for (int n : workers) {
          const RunConfig config{tile, batch, n, channel == "shared"};
          std::vector<RunResult> runs;
          for (int rep = 0; rep < reps; ++rep) {
            RunResult r = run_once(options, config,
                                   temp.path() / ("run-" + std::to_string(run_index)), run_index);
            ++run_index;
            char final_ms[32];
            std::snprintf(final_ms, sizeof final_ms, "%.1f", r.final_upload_ms);
            const std::string label =
                "load " + r.load_before + " -> " + r.load_after +
                (r.cut_off ? std::string("; cut off after --max-seconds")
                           : std::string("; last upload (completes the job, writes EXR+PNG) ") +
                                 final_ms + " ms");
            print_row(r, label.c_str());
            for (const std::string& p : r.problems) std::printf("    PROBLEM: %s\n", p.c_str());
            for (size_t i = 0; i < r.server_log.size() && i < 5; ++i) {
              std::printf("    server: %s\n", r.server_log[i].c_str());
            }
            runs.push_back(std::move(r));
          }
          medians.push_back(median_of(runs));
        }
      }
    }
    std::printf("\nmedians over %d rep(s):\n", reps);
    print_header();
    bool ok = true;
    for (const RunResult& m : medians) {
      print_row(m, "");
      ok = ok && m.problems.empty();
    }
    std::printf("load average at end: %s\n", load_average().c_str());
    std::printf(
        "res/s(client): results accepted / (workers released -> last accepted reply); "
        "merged/s(server): results_merged / (job's started_unix_ms -> finished_unix_ms: first "
        "lease to\n"
        "the last merge; the server stamps finished before writing the output).\n"
        "proto B/res: protobuf payloads of LeaseUnit request+reply and UploadResult "
        "request+reply (no gRPC/HTTP2 framing). early%%: uploads sent before the tile's "
        "previous batch was acknowledged (stored as pending, merged later).\n"
        "srv CPU ms/res: the server's CPU from the clock's start (every worker registered) to the "
        "job's end per accepted result; srv CPU s listen: its CPU at listening (exec, linking, "
        "store, gRPC set-up: a fixed cost of the run);\n"
        "ms/res life: its CPU from exec to the job's end per result (start-up included). The "
        "marginal cost per result is the difference of two job sizes (tests/load/capacity.sh).\n");
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tessera-bench-merge: %s\n", e.what());
    return 1;
  }
}
