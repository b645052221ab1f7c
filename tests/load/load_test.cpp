// Load (docs/reliability.md, "Load"): one real tessera-server on loopback, 64 simulated workers
// and 20 jobs submitted at once. A simulated worker speaks the worker protocol over its own gRPC
// connection (Register, LeaseUnit, UploadResult), as bench/merge_throughput.cpp does, uploading
// precomputed results instead of rendering, so the load is the server's.
//
// Every job must finish within a generous bound (a deadlock or a lost unit would leave one
// unfinished), with every unit accepted exactly once (the client's tally), results_merged ==
// units_done == units_total, no result dropped, and every pixel of every tile holding exactly the
// job's spp in the store. The test prints the lease latencies (p50, p99, max) and the rate.
// TESSERA_LOAD_WORKERS, TESSERA_LOAD_JOBS, TESSERA_LOAD_SPP (units per job = 16 x spp) and
// TESSERA_LOAD_BOUND_S change the sizes; TESSERA_LOAD_SERVER_BIN runs another tessera-server
// binary (to compare two builds on the same test). Two tests: one call per unit (LeaseUnit,
// UploadResult, as workers before batched calls), and batched calls (LeaseUnit with max_units =
// TESSERA_LOAD_PER_CALL, default 16, and one UploadResults for every unit it holds).
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include "accum/accumulation.h"
#include "accum/accumulation_codec.h"
#include "job/job_plan.h"
#include "process.h"
#include "store/sqlite.h"
#include "tessera/v1/job_service.grpc.pb.h"
#include "tessera/v1/worker_service.grpc.pb.h"
#include "wire/rpc_channel.h"
#include "wire/scene_bundle.h"

namespace tessera::load {
namespace {

using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

/// User + system CPU seconds of process `pid` so far (/proc/PID/stat fields 14 and 15).
double cpu_seconds(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  std::getline(in, line);
  const size_t close = line.rfind(')');  // the command name may contain spaces
  if (close == std::string::npos) return 0;
  std::istringstream fields(line.substr(close + 2));
  std::string field;
  for (int i = 3; i <= 13; ++i) fields >> field;
  double utime = 0, stime = 0;
  fields >> utime >> stime;
  return (utime + stime) / double(sysconf(_SC_CLK_TCK));
}

/// True when the server executable prints "image module loaded" (older servers load the module
/// silently, before listening or after).
bool says_when_module_loaded(const std::string& server_bin) {
  return e2e::read_text(server_bin).find("tessera-server: image module loaded (") !=
         std::string::npos;
}

int env_int(const char* name, int fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::max(1, std::atoi(v)) : fallback;
}

/// The jobs: 64x64 Cornell boxes in 16 tiles of 16x16, 8 spp (TESSERA_LOAD_SPP) in batches of
/// 1: 128 units each.
constexpr int kSize = 64, kTile = 16;
constexpr uint32_t kBatch = 1;

/// Each simulated worker has its own TCP connection, as separate processes would (gRPC would
/// otherwise share one between channels with equal arguments). Its calls wait for the connection
/// (wait_for_ready) within their deadline, as a real worker retries with backoff: 64 connections
/// opened at once can see a transient connect failure, which is not what this test measures.
std::shared_ptr<grpc::Channel> own_channel(const std::string& address) {
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(wire::kMaxMessageBytes);
  args.SetMaxSendMessageSize(wire::kMaxMessageBytes);
  args.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);
  return grpc::CreateCustomChannel(address, grpc::InsecureChannelCredentials(), args);
}

/// A result for every (tile, samples): sums that depend on the tile, `samples` per pixel.
class ResultBank {
 public:
  explicit ResultBank(const JobPlan& plan) {
    const auto tiles = plan.tiles();
    for (uint32_t b = 0; b < plan.batch_count(); ++b) {
      const uint32_t samples = plan.batch_end(b) - plan.batch_begin(b);
      for (size_t t = 0; t < tiles.size(); ++t) {
        auto& bytes = bytes_[{uint32_t(t), samples}];
        if (!bytes.empty()) continue;
        Accumulation acc(tiles[t]);
        for (size_t i = 0; i < acc.pixels(); ++i) {
          for (int c = 0; c < 3; ++c) acc.rgb[i * 3 + size_t(c)] = 0.25 * samples + 0.01 * double(c + t);
          acc.lum2[i] = 0.1 * samples;
          acc.count[i] = samples;
        }
        bytes = encode_accumulation(acc);
      }
    }
  }
  const std::string& get(uint32_t tile, uint32_t samples) const { return bytes_.at({tile, samples}); }

 private:
  std::map<std::pair<uint32_t, uint32_t>, std::string> bytes_;
};

struct Shared {
  std::mutex mu;
  std::map<std::pair<uint64_t, uint64_t>, int> accepted;  ///< (job, tile*batches+batch) -> times
  std::vector<double> lease_ms;                           ///< leases that got a unit
  uint64_t dropped = 0, no_work = 0;
  std::string error;
  std::atomic<bool> stop{false};
};

/// One unit leased: what its upload names.
struct Held {
  std::string lease_id;
  v1::WorkUnit unit;
};

/// `per_call` 1: LeaseUnit and UploadResult per unit; more: LeaseUnit with max_units and one
/// UploadResults for every unit held.
void simulated_worker(int index, const std::string& address, const ResultBank& bank,
                      uint32_t batches, uint32_t per_call, Shared& shared) {
  auto stub = v1::WorkerService::NewStub(own_channel(address));
  auto fail = [&](const std::string& what, const grpc::Status& s) {
    std::lock_guard lock(shared.mu);
    if (shared.error.empty()) {
      shared.error = "worker " + std::to_string(index) + ": " + what + ": " + wire::status_line(s);
    }
    shared.stop = true;
  };
  v1::RegisterRequest reg;
  reg.set_name("load-" + std::to_string(index));
  reg.set_threads(1);
  reg.set_isa("load");
  reg.set_version("load");
  v1::RegisterResponse me;
  {
    grpc::ClientContext ctx;
    wire::prepare_context(ctx, "", std::chrono::seconds(60));
    ctx.set_wait_for_ready(true);
    if (const auto s = stub->Register(&ctx, reg, &me); !s.ok()) return fail("Register", s);
  }
  std::vector<double> lease_ms;
  uint64_t dropped = 0, no_work = 0;
  while (!shared.stop) {
    v1::LeaseUnitRequest req;
    req.set_worker_id(me.worker_id());
    req.set_wait_ms(500);
    if (per_call > 1) req.set_max_units(per_call);
    v1::LeaseUnitResponse lease;
    const auto t0 = Clock::now();
    {
      grpc::ClientContext ctx;
      wire::prepare_context(ctx, "", std::chrono::seconds(60));
      ctx.set_wait_for_ready(true);
      if (const auto s = stub->LeaseUnit(&ctx, req, &lease); !s.ok()) return fail("LeaseUnit", s);
    }
    if (!lease.leased()) {
      ++no_work;
      continue;
    }
    lease_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    std::vector<Held> held;
    if (per_call > 1) {
      for (const v1::UnitLease& l : lease.leases()) held.push_back({l.lease_id(), l.unit()});
    } else {
      held.push_back({lease.lease_id(), lease.unit()});
    }
    const auto upload_of = [&](const Held& h) {
      v1::UploadResultRequest up;
      up.set_worker_id(me.worker_id());
      up.set_lease_id(h.lease_id);
      up.set_job_id(h.unit.job_id());
      up.set_tile(h.unit.tile());
      up.set_batch(h.unit.batch());
      up.set_accumulation(bank.get(h.unit.tile(), h.unit.sample_end() - h.unit.sample_begin()));
      up.set_isa("load");
      return up;
    };
    std::vector<bool> accepted;
    if (per_call > 1) {
      v1::UploadResultsRequest up;
      up.set_worker_id(me.worker_id());
      for (const Held& h : held) *up.add_results() = upload_of(h);
      v1::UploadResultsResponse results;
      grpc::ClientContext ctx;
      wire::prepare_context(ctx, "", std::chrono::seconds(120));
      ctx.set_wait_for_ready(true);
      if (const auto s = stub->UploadResults(&ctx, up, &results); !s.ok()) {
        return fail("UploadResults", s);
      }
      if (size_t(results.results_size()) != held.size()) {
        return fail("UploadResults answered " + std::to_string(results.results_size()) +
                        " results for " + std::to_string(held.size()),
                    grpc::Status::OK);
      }
      for (const auto& r : results.results()) accepted.push_back(r.accepted());
    } else {
      v1::UploadResultResponse result;
      grpc::ClientContext ctx;
      wire::prepare_context(ctx, "", std::chrono::seconds(120));
      ctx.set_wait_for_ready(true);
      if (const auto s = stub->UploadResult(&ctx, upload_of(held.front()), &result); !s.ok()) {
        return fail("UploadResult", s);
      }
      accepted.push_back(result.accepted());
    }
    for (size_t i = 0; i < held.size(); ++i) {
      const v1::WorkUnit& u = held[i].unit;
      if (accepted[i]) {
        std::lock_guard lock(shared.mu);
        ++shared.accepted[{u.job_id(), uint64_t(u.tile()) * batches + u.batch()}];
      } else {
        ++dropped;
      }
    }
  }
  std::lock_guard lock(shared.mu);
  shared.lease_ms.insert(shared.lease_ms.end(), lease_ms.begin(), lease_ms.end());
  shared.dropped += dropped;
  shared.no_work += no_work;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t rank = size_t(std::ceil(p / 100.0 * double(v.size())));
  return v[std::clamp<size_t>(rank, 1, v.size()) - 1];
}

/// The load test with `per_call` units per LeaseUnit and results per upload.
void run_load(uint32_t per_call) {
  const int workers = env_int("TESSERA_LOAD_WORKERS", 64);
  const int jobs = env_int("TESSERA_LOAD_JOBS", 20);
  const uint32_t kSpp = uint32_t(env_int("TESSERA_LOAD_SPP", 8));
  const auto bound = std::chrono::seconds(env_int("TESSERA_LOAD_BOUND_S", 600));
  const fs::path dir = fs::temp_directory_path() / ("tessera-load-" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const JobPlan plan = make_job_plan(kSize, kSize, kTile, kSpp, kBatch);
  const ResultBank bank(plan);

  // The server (lease 60 s: a simulated worker holds a lease for milliseconds; an expiry here
  // would mean a stall, and shows as leases_expired).
  const fs::path port_file = dir / "port";
  const char* other_server = std::getenv("TESSERA_LOAD_SERVER_BIN");
  const std::string server_bin = other_server && *other_server ? other_server : TESSERA_SERVER_BIN;
  auto server = std::make_unique<e2e::Process>(
      std::vector<std::string>{server_bin, "--grpc", "127.0.0.1:0", "--http", "127.0.0.1:0", "--db",
                               (dir / "farm.db").string(), "--output-dir",
                               (dir / "outputs").string(), "--port-file", port_file.string(),
                               "--lease-seconds", "60"},
      dir / "server.log");
  const auto start_deadline = Clock::now() + std::chrono::seconds(120);
  while (!fs::exists(port_file)) {
    ASSERT_TRUE(server->running()) << e2e::read_text(dir / "server.log");
    ASSERT_LT(Clock::now(), start_deadline) << "tessera-server did not start";
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  const std::string address = "127.0.0.1:" + std::to_string(std::stoi(e2e::read_text(port_file)));
  // The server's image module (OpenImageIO) is a start's fixed cost (0.3-0.5 s of CPU; seconds
  // of wall time on a busy machine), not serving's. Servers load it before they listen
  // (server/app/main.cpp); an older build that loaded it after listening is measured from the line
  // that says it is loaded, one that says nothing from listening.
  if (says_when_module_loaded(server_bin)) {
    while (e2e::read_text(dir / "server.log").find("image module") == std::string::npos) {
      ASSERT_TRUE(server->running()) << e2e::read_text(dir / "server.log");
      ASSERT_LT(Clock::now(), start_deadline) << "tessera-server did not load its image module";
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
  const double cpu_at_listening = cpu_seconds(server->pid());  // a start's fixed cost
  auto job_stub = v1::JobService::NewStub(wire::make_channel(address));

  Shared shared;
  std::vector<std::thread> threads;
  for (int i = 0; i < workers; ++i) {
    threads.emplace_back(simulated_worker, i, address, std::cref(bank), plan.batch_count(),
                         per_call, std::ref(shared));
  }
  // The 20 jobs arrive at once, while the workers already ask for work.
  const v1::SceneBundle bundle =
      wire::bundle_to_proto(wire::bundle_from_disk(fs::path(TESSERA_SOURCE_DIR) / "scenes" / "cornell.json"));
  std::vector<uint64_t> ids(size_t(jobs), 0);
  const auto t_submit = Clock::now();
  {
    std::vector<std::thread> submitters;
    for (int j = 0; j < jobs; ++j) {
      submitters.emplace_back([&, j] {
        v1::SubmitJobRequest req;
        *req.mutable_bundle() = bundle;
        req.set_priority(j % 3);  // three priority levels interleave
        auto* o = req.mutable_options();
        o->set_width(kSize);
        o->set_height(kSize);
        o->set_spp(kSpp);
        o->set_tile_size(kTile);
        o->set_batch_spp(kBatch);
        v1::SubmitJobResponse reply;
        grpc::ClientContext ctx;
        wire::prepare_context(ctx, "", std::chrono::seconds(120));
        const auto s = job_stub->SubmitJob(&ctx, req, &reply);
        EXPECT_TRUE(s.ok()) << wire::status_line(s);
        ids[size_t(j)] = reply.job().id();
      });
    }
    for (auto& t : submitters) t.join();
  }

  // Every job must end within the bound.
  std::vector<v1::JobInfo> infos(static_cast<size_t>(jobs));
  bool all_done = false;
  const auto deadline = t_submit + bound;
  while (!all_done && Clock::now() < deadline && !shared.stop) {
    all_done = true;
    for (int j = 0; j < jobs; ++j) {
      v1::GetJobRequest req;
      req.set_job_id(ids[size_t(j)]);
      grpc::ClientContext ctx;
      wire::prepare_context(ctx, "", std::chrono::seconds(60));
      const auto s = job_stub->GetJob(&ctx, req, &infos[size_t(j)]);
      ASSERT_TRUE(s.ok()) << wire::status_line(s);
      all_done = all_done && infos[size_t(j)].state() == v1::JOB_STATE_DONE;
    }
    if (!all_done) std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - t_submit).count();
  const double cpu_at_end = cpu_seconds(server->pid());
  shared.stop = true;
  for (auto& t : threads) t.join();
  ASSERT_TRUE(shared.error.empty()) << shared.error;
  ASSERT_TRUE(all_done) << "not every job finished within " << bound.count()
                        << " s (a deadlock or a lost unit); server log in " << dir;

  // Nothing lost, nothing twice.
  const uint64_t units_per_job = uint64_t(plan.tile_count()) * plan.batch_count();
  uint64_t total = 0;
  for (int j = 0; j < jobs; ++j) {
    const auto& c = infos[size_t(j)].counters();
    SCOPED_TRACE("job " + std::to_string(ids[size_t(j)]));
    EXPECT_EQ(c.units_total(), units_per_job);
    EXPECT_EQ(c.units_done(), c.units_total());
    EXPECT_EQ(c.results_merged(), c.units_total());
    EXPECT_EQ(c.results_dropped(), 0u);
    EXPECT_EQ(c.leases_expired(), 0u);
    total += c.results_merged();
  }
  EXPECT_EQ(shared.accepted.size(), units_per_job * uint64_t(jobs));
  for (const auto& [unit, times] : shared.accepted) {
    ASSERT_EQ(times, 1) << "job " << unit.first << " unit " << unit.second << " accepted " << times
                        << " times";
  }
  EXPECT_EQ(shared.dropped, 0u);
  {
    server::Database store((dir / "farm.db").string());
    auto q = store.prepare("SELECT job_id, tile, accumulation FROM tile_checkpoints");
    uint64_t tiles = 0;
    while (q->step()) {
      ++tiles;
      const Accumulation acc = decode_accumulation(q->blob(2));
      for (uint32_t n : acc.count) {
        ASSERT_EQ(n, kSpp) << "job " << q->int64(0) << " tile " << q->int64(1);
      }
    }
    EXPECT_EQ(tiles, uint64_t(plan.tile_count()) * uint64_t(jobs));
    // Nothing waits and every done job's sums are in their checkpoints.
    auto left = store.prepare("SELECT COUNT(*) FROM results");
    ASSERT_TRUE(left->step());
    EXPECT_EQ(left->int64(0), 0);
  }

  std::cout << "[load] " << workers << " simulated workers, " << per_call
            << " unit(s) per call, " << jobs << " jobs x " << units_per_job
            << " units = " << total << " results merged in " << seconds << " s ("
            << double(total) / seconds << " results/s); lease latency (lease calls that got work, "
            << shared.lease_ms.size() << "): p50 " << percentile(shared.lease_ms, 50) << " ms, p99 "
            << percentile(shared.lease_ms, 99) << " ms, max "
            << percentile(shared.lease_ms, 100) << " ms; empty long polls " << shared.no_work
            << "; server CPU " << cpu_at_listening << " s at listening, "
            << 1000.0 * (cpu_at_end - cpu_at_listening) / double(std::max<uint64_t>(total, 1))
            << " ms per result after (submits, leases, uploads, outputs)" << std::endl;
  ::testing::Test::RecordProperty("lease_p99_ms", std::to_string(percentile(shared.lease_ms, 99)));
  server.reset();
  if (!::testing::Test::HasFailure()) fs::remove_all(dir);
}

TEST(Load, SixtyFourWorkersTwentyJobsNothingLostNoDeadlock) { run_load(1); }

TEST(Load, BatchedCallsNothingLostNoDeadlock) {
  run_load(uint32_t(env_int("TESSERA_LOAD_PER_CALL", 16)));
}

}  // namespace
}  // namespace tessera::load
