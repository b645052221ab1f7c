#include "merge_bench_run.h"

#include <sys/resource.h>

#include <algorithm>
#include <fstream>
#include <latch>
#include <thread>

#include "job/job_plan.h"
#include "merge_bench_results.h"
#include "merge_bench_server.h"
#include "merge_bench_worker.h"
#include "tessera/v1/job_service.grpc.pb.h"
#include "wire/rpc_channel.h"
#include "wire/scene_bundle.h"

namespace tessera::bench_merge {

namespace {

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


/// The workers' tallies added up.
struct TallyTotals {
  std::vector<double> lease_ms, upload_ms, later_lease_ms;  ///< later: each worker's calls after its first
  uint64_t accepted = 0, dropped = 0, early = 0, proto_bytes = 0, results = 0;
  Clock::time_point last;  ///< the last accepted upload (start when none)
};

/// The tallies' totals; r.final_upload_ms receives the last accepted upload's time.
TallyTotals totals_of(const std::vector<WorkerTally>& tallies, Clock::time_point start, RunResult& r) {
  TallyTotals totals;
  totals.last = start;
  for (const WorkerTally& t : tallies) {
    totals.lease_ms.insert(totals.lease_ms.end(), t.lease_ms.begin(), t.lease_ms.end());
    if (t.lease_ms.size() > 1) {
      totals.later_lease_ms.insert(totals.later_lease_ms.end(), t.lease_ms.begin() + 1, t.lease_ms.end());
    }
    totals.upload_ms.insert(totals.upload_ms.end(), t.upload_ms.begin(), t.upload_ms.end());
    totals.accepted += t.accepted;
    totals.dropped += t.dropped;
    totals.early += t.early;
    totals.proto_bytes += t.proto_bytes;
    totals.results += t.results;
    if (t.accepted > 0 && t.last_accept >= totals.last) {
      totals.last = t.last_accept;
      r.final_upload_ms = t.last_accept_upload_ms;
    }
  }
  return totals;
}

/// Each worker's calls, one line each: kind, worker, begin and end (ns), units, first lease id.
void write_client_trace(const std::string& path, const std::vector<WorkerTally>& tallies) {
  std::ofstream out(path);
  for (size_t w = 0; w < tallies.size(); ++w) {
    for (const CallRecord& c : tallies[w].calls) {
      out << c.kind << ' ' << w << ' ' << c.begin_ns << ' ' << c.end_ns << ' ' << c.units << ' ' << c.lease_id
          << '\n';
    }
  }
}

/// The server's log without its start and stop lines.
std::vector<std::string> server_log_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream log(text);
  for (std::string line; std::getline(log, line);) {
    if (line.find("listening on") == std::string::npos && line.find("shutting down") == std::string::npos) {
      lines.push_back(line);
    }
  }
  return lines;
}

}  // namespace

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
  TallyTotals t = totals_of(tallies, start, r);
  std::vector<double>& lease_ms = t.lease_ms;
  std::vector<double>& upload_ms = t.upload_ms;
  const uint64_t accepted = t.accepted, results = t.results;
  const Clock::time_point last = t.last;
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
  r.lease_p99_later = percentile(t.later_lease_ms, 99);
  r.upload_p50 = percentile(upload_ms, 50);
  r.upload_p99 = percentile(upload_ms, 99);
  r.upload_max = upload_ms.empty() ? 0 : *std::max_element(upload_ms.begin(), upload_ms.end());
  r.accum_bytes = bank.mean_bytes();
  r.proto_bytes = results ? double(t.proto_bytes) / double(results) : 0;
  r.accepted = accepted;
  r.server_cpu_listen_s = server.cpu_at_listening_s();
  r.server_cpu_run_s = server_cpu1 - server_cpu0;
  r.server_cpu_ms = accepted ? (server_cpu1 - server_cpu0) * 1000.0 / double(accepted) : 0;
  r.server_cpu_life_ms = accepted ? server_cpu1 * 1000.0 / double(accepted) : 0;
  r.client_cpu_ms = accepted ? (client_cpu1 - client_cpu0) * 1000.0 / double(accepted) : 0;
  r.early_fraction = results ? double(t.early) / double(results) : 0;
  check_final(job, shared, accepted, t.dropped, r);
  if (!trace_prefix.empty()) write_client_trace(trace_prefix + ".client", tallies);
  r.server_log = server_log_lines(server.log_text());
  return r;
}

}  // namespace tessera::bench_merge
