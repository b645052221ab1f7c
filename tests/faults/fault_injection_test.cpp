// Fault injection with real processes (docs/reliability.md): tessera-server, tessera-worker and
// the tessera CLI on loopback (and, for the network cut, in network namespaces the test
// creates). Each test runs several rounds; in each round a job renders while the test injects
// faults at seeded random moments, and then the job must pass faults::verify_job: done, every
// unit accepted and merged exactly once, and the pixels bit-identical to `tessera-worker
// render`. The seed is printed first; TESSERA_FAULT_SEED=N replays the same fault moments and
// TESSERA_FAULT_ROUNDS=N changes the number of rounds.
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <thread>

#include "farm_cluster.h"
#include "fault_support.h"

namespace tessera::faults {
namespace {

using e2e::CommandResult;
using e2e::FarmCluster;
using e2e::kPatience;
using e2e::Process;

std::vector<std::string> with_scene(const std::vector<std::string>& options) {
  std::vector<std::string> args = {cornell_scene().string()};
  args.insert(args.end(), options.begin(), options.end());
  return args;
}

bool is_final(const v1::JobInfo& j) {
  return j.state() == v1::JOB_STATE_DONE || j.state() == v1::JOB_STATE_FAILED ||
         j.state() == v1::JOB_STATE_CANCELLED;
}

/// `count` distinct thresholds in [1, limit], sorted: the merged-result counts at which faults
/// are injected (a count, not a time, so the moment is inside the job on any machine).
std::vector<uint32_t> fault_points(std::mt19937_64& rng, uint32_t limit, int count) {
  std::uniform_int_distribution<uint32_t> pick(1, std::max<uint32_t>(1, limit));
  std::vector<uint32_t> points;
  for (int i = 0; i < count; ++i) points.push_back(pick(rng));
  std::sort(points.begin(), points.end());
  return points;
}

/// A random extra delay after a threshold is reached, so the fault does not always land right
/// after a poll.
void jitter(std::mt19937_64& rng, int max_ms) {
  std::this_thread::sleep_for(
      std::chrono::milliseconds(std::uniform_int_distribution<int>(0, max_ms)(rng)));
}

size_t count_lines(const std::filesystem::path& log, const std::string& needle) {
  std::ifstream in(log);
  std::string line;
  size_t n = 0;
  while (std::getline(in, line)) n += line.find(needle) != std::string::npos;
  return n;
}

CliRunner cli_of(FarmCluster& farm) {
  return [&farm](const std::vector<std::string>& args) { return farm.cli(args); };
}

// ---------------------------------------------------------------------------------------------

TEST(Faults, WorkersSigkilledAtRandomMomentsOverManyRounds) {
  const uint64_t seed = fault_seed("WorkersSigkilledAtRandomMoments");
  std::mt19937_64 rng(seed);
  const int rounds = fault_rounds(6);
  FarmCluster farm("faults-worker-kill");
  farm.start_server({"--lease-seconds", "1"});
  std::vector<size_t> slots;
  for (int i = 0; i < 3; ++i) slots.push_back(farm.start_worker({"--threads", "1"}));

  int kills = 0, kills_after_end = 0;
  for (int round = 0; round < rounds && !HasFailure(); ++round) {
    // Odd rounds use the default progressive schedule, even rounds many fixed 2-spp batches.
    const auto options = tiny_job(rng() % 1000, 256, round % 2 == 1 ? 0 : 2);
    const uint64_t id = farm.submit(with_scene(options));
    ASSERT_NE(id, 0u);
    const uint32_t total = farm.job(id).counters().units_total();
    const auto points = fault_points(rng, total * 9 / 10, 1 + int(rng() % 3));
    std::ostringstream seen;
    for (uint32_t point : points) {
      const v1::JobInfo at = farm.wait_job(
          id, [&](const v1::JobInfo& j) { return is_final(j) || j.counters().results_merged() >= point; },
          "results to reach the kill point");
      if (is_final(at)) {
        ++kills_after_end;
        break;
      }
      jitter(rng, 50);
      const size_t slot = rng() % slots.size();
      farm.worker(slots[slot]).signal(SIGKILL);
      ASSERT_TRUE(farm.worker(slots[slot]).wait_for(kPatience).has_value());
      slots[slot] = farm.start_worker({"--threads", "1"});  // a fresh worker takes its place
      ++kills;
      seen << " kill@" << at.counters().results_merged();
    }
    const v1::JobInfo final_info = farm.wait_final(id);
    ASSERT_TRUE(is_final(final_info));
    const JobOutcome o = verify_job(cli_status(cli_of(farm), id), farm.db_path(), options,
                                    farm.dir(), "round " + std::to_string(round));
    std::cout << "[faults] worker-kill round " << round << ": " << o.units_total << " units,"
              << seen.str() << "; leases_expired " << o.leases_expired << ", results_dropped "
              << o.results_dropped << (o.ok ? ": OK" : ": FAILED") << std::endl;
  }
  std::cout << "[faults] worker-kill: " << rounds << " rounds, " << kills << " workers SIGKILLed ("
            << kills_after_end << " kill points fell after the job's end)" << std::endl;
  EXPECT_GT(kills, 0) << "no kill landed inside a job: the test proved nothing";
}

// ---------------------------------------------------------------------------------------------

/// The worker (by name) holds a lease according to the server.
bool holds_lease(FarmCluster& farm, const std::string& name) {
  v1::ListWorkersRequest request;
  v1::ListWorkersResponse response;
  auto ctx = FarmCluster::context();
  const grpc::Status status = farm.jobs().ListWorkers(ctx.get(), request, &response);
  EXPECT_TRUE(status.ok()) << status.error_message();
  for (const auto& w : response.workers()) {
    if (w.name() == name && w.online() && w.job_id() != 0) return true;
  }
  return false;
}

TEST(Faults, WorkerStoppedPastItsLeaseIsFencedOffWhenItContinues) {
  const uint64_t seed = fault_seed("WorkerStoppedPastItsLease");
  std::mt19937_64 rng(seed);
  const int rounds = fault_rounds(4);
  FarmCluster farm("faults-sigstop");
  farm.start_server({"--lease-seconds", "1"});
  const size_t victim = farm.start_worker({"--threads", "1"});
  farm.start_worker({"--threads", "1"});
  const std::string victim_name = "e2e-worker-" + std::to_string(victim);
  const auto victim_log = farm.dir() / ("worker-" + std::to_string(victim) + ".log");

  int stops = 0, fenced_uploads = 0, fenced_heartbeats = 0;
  for (int round = 0; round < rounds && !HasFailure(); ++round) {
    // Larger batches here: the worker spends most of its time rendering, holding a lease.
    const auto options = tiny_job(rng() % 1000, 512, 8);
    const uint64_t id = farm.submit(with_scene(options));
    ASSERT_NE(id, 0u);
    const uint32_t total = farm.job(id).counters().units_total();
    const uint32_t point = fault_points(rng, total / 2, 1).front();
    farm.wait_job(id, [&](const v1::JobInfo& j) { return j.counters().results_merged() >= point; },
                  "results to reach the stop point");
    jitter(rng, 50);
    const size_t uploads_before = count_lines(victim_log, "result dropped by the server");
    const size_t heartbeats_before = count_lines(victim_log, "lease gone");

    // SIGSTOP at a moment when the server says the worker holds a lease (between two units it
    // holds none: continue it and try again a little later).
    bool stopped_holding = false;
    for (int attempt = 0; attempt < 50 && !stopped_holding; ++attempt) {
      farm.worker(victim).signal(SIGSTOP);
      if (holds_lease(farm, victim_name)) {
        stopped_holding = true;
      } else {
        farm.worker(victim).signal(SIGCONT);
        jitter(rng, 30);
      }
    }
    ASSERT_TRUE(stopped_holding) << "the worker never held a lease when stopped";
    const uint32_t expired_before = farm.job(id).counters().leases_expired();
    // Past the lease: the reaper gives the unit back to the queue (the other worker redoes it),
    // or the result the worker had sent just before the stop was accepted after all.
    const bool expired = poll_until(
        [&] {
          return farm.job(id).counters().leases_expired() > expired_before ||
                 !holds_lease(farm, victim_name);
        },
        kPatience);
    ASSERT_TRUE(expired);
    jitter(rng, 1500);
    farm.worker(victim).signal(SIGCONT);
    ++stops;

    farm.wait_final(id);
    const JobOutcome o = verify_job(cli_status(cli_of(farm), id), farm.db_path(), options,
                                    farm.dir(), "round " + std::to_string(round));
    // The continued worker finds out: its late result is dropped by the server, or its next
    // heartbeat is answered "lease gone" and it drops the unit itself.
    size_t uploads = 0, heartbeats = 0;
    poll_until(
        [&] {
          uploads = count_lines(victim_log, "result dropped by the server") - uploads_before;
          heartbeats = count_lines(victim_log, "lease gone") - heartbeats_before;
          return uploads + heartbeats > 0 || o.leases_expired == 0;
        },
        std::chrono::seconds(30));
    fenced_uploads += int(uploads);
    fenced_heartbeats += int(heartbeats);
    std::cout << "[faults] sigstop round " << round << ": stopped at " << point << "/" << total
              << " merged; leases_expired " << o.leases_expired << ", results_dropped "
              << o.results_dropped << "; the worker saw " << uploads << " late result(s) dropped, "
              << heartbeats << " lease(s) gone at heartbeat" << (o.ok ? ": OK" : ": FAILED")
              << std::endl;
    if (o.leases_expired > 0) {
      EXPECT_GT(uploads + heartbeats, 0u) << "a lease expired but the worker was never told";
    }
  }
  std::cout << "[faults] sigstop: " << rounds << " rounds, " << stops << " stops past the lease; "
            << fenced_uploads << " late results fenced off by the server, " << fenced_heartbeats
            << " units dropped by the worker on a 'lease gone' heartbeat" << std::endl;
}

// ---------------------------------------------------------------------------------------------

TEST(Faults, ServerSigkilledWhileCommittingResultsAndRestarted) {
  const uint64_t seed = fault_seed("ServerSigkilledWhileCommitting");
  std::mt19937_64 rng(seed);
  const int rounds = fault_rounds(4);
  FarmCluster farm("faults-server-kill");
  farm.start_server({"--lease-seconds", "2"});
  for (int i = 0; i < 3; ++i) farm.start_worker({"--threads", "1"});

  int kills = 0;
  for (int round = 0; round < rounds && !HasFailure(); ++round) {
    // Odd rounds use the default progressive schedule, even rounds many fixed 2-spp batches.
    const auto options = tiny_job(rng() % 1000, 256, round % 2 == 1 ? 0 : 2);
    const uint64_t id = farm.submit(with_scene(options));
    ASSERT_NE(id, 0u);
    const uint32_t total = farm.job(id).counters().units_total();
    const auto points = fault_points(rng, total * 9 / 10, 1 + int(rng() % 2));
    std::ostringstream seen;
    for (uint32_t point : points) {
      const v1::JobInfo before = farm.wait_job(
          id, [&](const v1::JobInfo& j) { return is_final(j) || j.counters().results_merged() >= point; },
          "results to reach the kill point");
      if (is_final(before)) break;
      // Three workers upload continuously: a kill at a random microsecond lands inside or
      // between result transactions.
      std::this_thread::sleep_for(
          std::chrono::microseconds(std::uniform_int_distribution<int>(0, 20000)(rng)));
      // The workers are stopped across the restart so that the look below sees the store as the
      // restarted server left it: a worker reconnecting first would hold fresh leases (a race
      // that failed this test in CI). Their uploads already in flight still reach the server
      // before the kill.
      for (int w = 0; w < 3; ++w) farm.worker(w).signal(SIGSTOP);
      farm.kill_server();
      ++kills;
      farm.start_server();  // same database and port
      const v1::JobInfo after = farm.job(id);
      for (int w = 0; w < 3; ++w) farm.worker(w).signal(SIGCONT);  // they reconnect by themselves
      // Nothing accepted before the kill is lost (more may have been accepted after the look).
      EXPECT_GE(after.counters().units_done(), before.counters().units_done());
      EXPECT_GE(after.counters().results_merged(), before.counters().results_merged());
      EXPECT_EQ(after.counters().units_leased(), 0u) << "leases from before the crash survived";
      seen << " kill@" << before.counters().results_merged() << "->"
           << after.counters().results_merged();
    }
    farm.wait_final(id);
    const JobOutcome o = verify_job(cli_status(cli_of(farm), id), farm.db_path(), options,
                                    farm.dir(), "round " + std::to_string(round));
    std::cout << "[faults] server-kill round " << round << ": " << o.units_total << " units,"
              << seen.str() << " (merged seen before -> after restart); leases_expired "
              << o.leases_expired << ", results_dropped " << o.results_dropped
              << (o.ok ? ": OK" : ": FAILED") << std::endl;
  }
  std::cout << "[faults] server-kill: " << rounds << " rounds, " << kills
            << " server SIGKILLs and restarts" << std::endl;
  EXPECT_GT(kills, 0) << "no kill landed inside a job: the test proved nothing";
}

// ---------------------------------------------------------------------------------------------
// The network cut: the server in one network namespace, a worker in another, joined by a veth
// pair whose link the test takes down and up.

std::string ip_binary() {
  for (const char* p : {"/usr/sbin/ip", "/sbin/ip", "/bin/ip", "/usr/bin/ip"}) {
    if (access(p, X_OK) == 0) return p;
  }
  return "";
}

/// Runs `ip ARGS...`; true on success. The output goes to `log_stem`.{out,err}.
bool ip(const std::filesystem::path& log_stem, const std::vector<std::string>& args) {
  std::vector<std::string> argv = {ip_binary()};
  argv.insert(argv.end(), args.begin(), args.end());
  return e2e::run_command(argv, log_stem, {}, std::chrono::seconds(60)).exit_code == 0;
}

/// Two namespaces, "server" and "worker", joined by a veth pair (10.213.0.1 <-> 10.213.0.2).
/// Removed (with their veth ends) when the object goes away.
class NetnsPair {
 public:
  explicit NetnsPair(const std::filesystem::path& dir) : dir_(dir) {
    const std::string tag = std::to_string(getpid());
    server_ns = "tessera-srv-" + tag;
    worker_ns = "tessera-wkr-" + tag;
    server_if = "tsv" + tag;
    worker_if = "twk" + tag;
  }
  /// Creates everything; false (with the reason in `why`) when `ip netns` is not permitted.
  bool create(std::string& why) {
    if (ip_binary().empty()) {
      why = "no `ip` binary (install iproute2: scripts/install-deps.sh)";
      return false;
    }
    if (!ip(dir_ / "netns-probe", {"netns", "add", server_ns})) {
      why = "`ip netns add` is not permitted here (needs root / CAP_SYS_ADMIN): " +
            e2e::read_text(dir_ / "netns-probe.err");
      return false;
    }
    created_server_ = true;
    created_worker_ = ip(dir_ / "netns-1", {"netns", "add", worker_ns});
    const bool ok =
        created_worker_ &&
        ip(dir_ / "netns-2", {"link", "add", server_if, "type", "veth", "peer", "name", worker_if}) &&
        ip(dir_ / "netns-3", {"link", "set", server_if, "netns", server_ns}) &&
        ip(dir_ / "netns-4", {"link", "set", worker_if, "netns", worker_ns}) &&
        ip(dir_ / "netns-5", {"-n", server_ns, "addr", "add", "10.213.0.1/24", "dev", server_if}) &&
        ip(dir_ / "netns-6", {"-n", worker_ns, "addr", "add", "10.213.0.2/24", "dev", worker_if}) &&
        ip(dir_ / "netns-7", {"-n", server_ns, "link", "set", server_if, "up"}) &&
        ip(dir_ / "netns-8", {"-n", worker_ns, "link", "set", worker_if, "up"}) &&
        ip(dir_ / "netns-9", {"-n", server_ns, "link", "set", "lo", "up"}) &&
        ip(dir_ / "netns-10", {"-n", worker_ns, "link", "set", "lo", "up"});
    if (!ok) why = "setting up the namespaces failed (logs in " + dir_.string() + ")";
    return ok;
  }
  ~NetnsPair() {
    if (created_worker_) ip(dir_ / "netns-del-w", {"netns", "del", worker_ns});
    if (created_server_) ip(dir_ / "netns-del-s", {"netns", "del", server_ns});
  }
  /// Takes the worker's end of the link down (false) or up (true).
  bool set_worker_link(bool up) {
    return ip(dir_ / ("link-" + std::to_string(link_changes_++)),
              {"-n", worker_ns, "link", "set", worker_if, up ? "up" : "down"});
  }
  /// argv prefixed to run inside `ns`.
  std::vector<std::string> in(const std::string& ns, const std::vector<std::string>& argv) const {
    std::vector<std::string> full = {ip_binary(), "netns", "exec", ns};
    full.insert(full.end(), argv.begin(), argv.end());
    return full;
  }

  std::string server_ns, worker_ns, server_if, worker_if;

 private:
  std::filesystem::path dir_;
  bool created_server_ = false, created_worker_ = false;
  int link_changes_ = 0;
};

/// The rounds of the network-cut test; the processes end when it returns, before `net` is
/// removed.
void netns_rounds(NetnsPair& net, const std::filesystem::path& dir) {
  const uint64_t seed = fault_seed("WorkerNetworkCut");
  std::mt19937_64 rng(seed);
  const int rounds = fault_rounds(2);
  const auto db = dir / "farm.db";
  const auto port_file = dir / "port";
  Process server(net.in(net.server_ns, {TESSERA_SERVER_BIN, "--grpc", "10.213.0.1:0", "--http", "10.213.0.1:0", "--insecure", "--db",
                                        db.string(), "--output-dir", (dir / "outputs").string(),
                                        "--port-file", port_file.string(), "--lease-seconds", "1"}),
                 dir / "server.log");
  ASSERT_TRUE(poll_until([&] { return std::filesystem::exists(port_file) || !server.running(); },
                         kPatience));
  ASSERT_TRUE(server.running()) << e2e::read_text(dir / "server.log");
  // The port file holds the number and a newline.
  const std::string address = "10.213.0.1:" + std::to_string(std::stoi(e2e::read_text(port_file)));
  // The victim is across the veth link; a second worker runs beside the server, so the job goes
  // on while the link is down.
  Process cut_worker(net.in(net.worker_ns, {TESSERA_WORKER_BIN, "--server", address, "--threads",
                                            "1", "--cache", (dir / "cache-w").string(), "--name",
                                            "across-the-link"}),
                     dir / "worker-across.log");
  Process near_worker(net.in(net.server_ns, {TESSERA_WORKER_BIN, "--server", address, "--threads",
                                             "1", "--cache", (dir / "cache-s").string(), "--name",
                                             "beside-the-server"}),
                      dir / "worker-beside.log");
  int commands = 0;
  const CliRunner cli = [&](const std::vector<std::string>& args) {
    std::vector<std::string> argv = {TESSERA_CLI_BIN, "--server", address};
    argv.insert(argv.end(), args.begin(), args.end());
    return e2e::run_command(net.in(net.server_ns, argv), dir / ("cli-" + std::to_string(commands++)),
                            {}, kPatience);
  };
  auto merged = [&](uint64_t id) {
    const nlohmann::json s = cli_status(cli, id);
    return s.is_null() ? uint64_t(0) : s.at("counters").at("results_merged").get<uint64_t>();
  };

  auto across_holds_lease = [&] {
    const CommandResult w = cli({"workers", "--json"});
    if (w.exit_code != 0) return false;
    for (const auto& worker : nlohmann::json::parse(w.out)) {
      if (worker.at("name") == "across-the-link" && !worker.at("job_id").is_null()) return true;
    }
    return false;
  };
  int cuts = 0, cuts_with_expiry = 0;
  for (int round = 0; round < rounds && !::testing::Test::HasFailure(); ++round) {
    // 16,384 small units (16 tiles of 8x8, batches of 1 spp): workers lease and upload them 16
    // per call, so a unit costs the farm well under a millisecond. The worker beside the server
    // is stopped (SIGSTOP) while the cut is tried, and the job has many units: otherwise the
    // whole job could be merged between two status reads of a loaded machine, leaving no lease
    // to cut. (Its local render for the comparison is 1M samples: cheap.)
    const std::vector<std::string> options = {"--width", "32", "--height", "32", "--tile", "8",
                                              "--spp", "1024", "--batch", "1", "--seed",
                                              std::to_string(rng() % 1000)};
    std::vector<std::string> submit = {"submit", cornell_scene().string(), "--json"};
    submit.insert(submit.end(), options.begin(), options.end());
    const CommandResult r = cli(submit);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const uint64_t id = nlohmann::json::parse(r.out).at("id").get<uint64_t>();
    const uint64_t total = cli_status(cli, id).at("counters").at("units_total").get<uint64_t>();
    const uint64_t point = fault_points(rng, uint32_t(total / 4), 1).front();
    ASSERT_TRUE(poll_until([&] { return merged(id) >= point; }, kPatience));
    near_worker.signal(SIGSTOP);
    // Cut while the worker across the link holds a lease. Cut first, then ask the server:
    // with the link down the worker can no longer deliver, so what the server says holds. If it
    // holds nothing, restore the link and try again a little later.
    // The count of expired leases is read before each cut: the worker's 1 s lease may expire
    // while the status after the cut is still on its way, and that expiry is the cut's too.
    nlohmann::json at_cut, during;
    uint64_t expired = 0, expired_before = 0;
    int down_ms = 0, attempts = 0;
    bool caught = false;
    while (!caught && attempts < 100 && merged(id) < total) {
      ++attempts;
      expired_before = cli_status(cli, id).at("counters").at("leases_expired").get<uint64_t>();
      ASSERT_TRUE(net.set_worker_link(false));
      caught = across_holds_lease();
      if (!caught) {
        ASSERT_TRUE(net.set_worker_link(true));
        jitter(rng, 100);
      }
    }
    const auto cut_at = std::chrono::steady_clock::now();
    if (caught) {
      at_cut = cli_status(cli, id);
      // Down for 3 to 5 s (longer than the 1 s lease), then up again.
      const int planned_ms = 3000 + std::uniform_int_distribution<int>(0, 2000)(rng);
      std::this_thread::sleep_until(cut_at + std::chrono::milliseconds(planned_ms));
      during = cli_status(cli, id);
      expired = during.at("counters").at("leases_expired").get<uint64_t>() - expired_before;
      down_ms = int(std::chrono::duration_cast<std::chrono::milliseconds>(
                        std::chrono::steady_clock::now() - cut_at)
                        .count());
      ASSERT_TRUE(net.set_worker_link(true));
      EXPECT_GT(expired, 0u) << "the worker held a lease when cut, yet no lease expired";
    } else {
      at_cut = during = cli_status(cli, id);
    }
    near_worker.signal(SIGCONT);
    cuts += caught;
    cuts_with_expiry += expired > 0;
    ASSERT_TRUE(poll_until(
        [&] {
          const nlohmann::json s = cli_status(cli, id);
          return s.is_null() || s.at("state") != "running";
        },
        kPatience));
    const JobOutcome o = verify_job(cli_status(cli, id), db, options, dir,
                                    "round " + std::to_string(round));
    std::cout << "[faults] netns round " << round << ": link down " << down_ms << " ms at "
              << at_cut.at("counters").at("results_merged") << "/" << total << " merged ("
              << during.at("counters").at("results_merged") << " when it came back up, "
              << during.at("state") << "; cut " << attempts << " time(s) to catch a lease" << (caught ? "" : ", never caught") << "); "
              << expired << " lease(s) expired during the cut; job totals: leases_expired " << o.leases_expired
              << ", results_dropped " << o.results_dropped << (o.ok ? ": OK" : ": FAILED")
              << std::endl;
  }
  EXPECT_EQ(cuts, rounds) << "a round never caught the worker holding a lease";
  // After the cuts the worker across the link must work again: a last job with it alone.
  if (!::testing::Test::HasFailure()) {
    near_worker.signal(SIGKILL);
    near_worker.wait_for(kPatience);
    const auto options = tiny_job(7, 64, 16);
    std::vector<std::string> submit = {"submit", cornell_scene().string(), "--json"};
    submit.insert(submit.end(), options.begin(), options.end());
    const CommandResult r = cli(submit);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const uint64_t id = nlohmann::json::parse(r.out).at("id").get<uint64_t>();
    ASSERT_TRUE(poll_until(
        [&] {
          const nlohmann::json s = cli_status(cli, id);
          return s.is_null() || (s.at("state") != "queued" && s.at("state") != "running");
        },
        kPatience));
    verify_job(cli_status(cli, id), db, options, dir, "after the cuts, the cut worker alone");
  }
  std::cout << "[faults] netns: " << rounds << " rounds, " << cuts << " link cuts restored ("
            << cuts_with_expiry << " caught a lease, which expired); the cut worker rendered a "
            << "job alone afterwards" << std::endl;
}

TEST(Faults, WorkerNetworkCutInANamespaceAndRestored) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("tessera-faults-netns-" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  {
    NetnsPair net(dir);
    std::string why;
    if (!net.create(why)) GTEST_SKIP() << "network-namespace test skipped: " << why;
    netns_rounds(net, dir);
  }
  if (HasFailure()) {
    for (const char* log : {"server.log", "worker-across.log", "worker-beside.log"}) {
      std::cerr << "----- " << log << "\n" << e2e::read_text(dir / log) << "\n";
    }
    std::cerr << "----- (files kept in " << dir << ")\n";
  } else {
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }
}

}  // namespace
}  // namespace tessera::faults
