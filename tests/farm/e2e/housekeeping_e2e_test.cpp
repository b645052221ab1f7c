// Housekeeping end to end: one server per database (a second one is refused naming the holder,
// also through a symbolic or a hard link to the file; a SIGKILLed one's successor gets the lock
// back), `tessera delete` of finished and cancelled jobs (outputs and space returned; a running
// or unknown job refused, exit 1), the --max-units and --max-unit-samples refusals at submit, a
// cancel stopping a worker in the middle of a huge batch, and lazy units (a submit writes rows
// per tile, not per unit).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "farm_cluster.h"
#include "process.h"
#include "store/sqlite.h"

namespace tessera::e2e {
namespace {

const std::string kTiny = (source_dir() / "tests" / "farm" / "data" / "tiny.json").string();

TEST(HousekeepingE2E, ASecondServerOnTheSameDatabaseIsRefused) {
  FarmCluster farm("db-lock");
  farm.start_server();
  const CommandResult second = run_command(
      {TESSERA_SERVER_BIN, "--db", farm.db_path().string(), "--grpc", "127.0.0.1:0", "--http",
       "127.0.0.1:0", "--output-dir", (farm.dir() / "outputs2").string()},
      farm.dir() / "second-server", {}, std::chrono::seconds(60));
  EXPECT_EQ(second.exit_code, 1);
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  EXPECT_NE(second.err.find("database " + farm.db_path().string() +
                            " is in use by tessera-server pid "),
            std::string::npos)
      << second.err;
  EXPECT_NE(second.err.find(std::string(" on host ") + host), std::string::npos) << second.err;
  EXPECT_EQ(std::count(second.err.begin(), second.err.end(), '\n'), 1) << second.err;
  // SIGKILL leaves no stale lock: the next server starts and serves.
  farm.kill_server();
  farm.start_server();
  const uint64_t id = farm.submit({kTiny, "--spp", "2"});
  EXPECT_NE(id, 0u);
  if (HasFailure()) farm.dump_logs();
}

TEST(HousekeepingE2E, ASecondServerThroughALinkToTheDatabaseIsRefused) {
  FarmCluster farm("db-lock-links");
  farm.start_server();
  const std::filesystem::path symlink = farm.dir() / "link.db";
  std::filesystem::create_directories(farm.dir() / "elsewhere");
  const std::filesystem::path hardlink = farm.dir() / "elsewhere" / "farm.db";
  std::filesystem::create_symlink(farm.db_path(), symlink);
  std::filesystem::create_hard_link(farm.db_path(), hardlink);
  const auto second_server = [&](const std::filesystem::path& db, const std::string& name) {
    return run_command({TESSERA_SERVER_BIN, "--db", db.string(), "--grpc", "127.0.0.1:0", "--http",
                        "127.0.0.1:0", "--output-dir", (farm.dir() / ("outputs-" + name)).string()},
                       farm.dir() / ("server-" + name), {}, std::chrono::seconds(60));
  };
  const CommandResult through_symlink = second_server(symlink, "symlink");
  EXPECT_EQ(through_symlink.exit_code, 1);
  EXPECT_NE(through_symlink.err.find("database " + symlink.string() +
                                     " is in use by tessera-server pid "),
            std::string::npos)
      << through_symlink.err;
  EXPECT_NE(through_symlink.err.find(" through " + farm.db_path().string()), std::string::npos)
      << through_symlink.err;
  const CommandResult through_hardlink = second_server(hardlink, "hardlink");
  EXPECT_EQ(through_hardlink.exit_code, 1);
  EXPECT_NE(through_hardlink.err.find("database " + hardlink.string() + " is in use by another"
                                      " tessera-server through another path to the same file"),
            std::string::npos)
      << through_hardlink.err;
  // Neither wrote an output folder: they never served.
  EXPECT_FALSE(std::filesystem::exists(farm.dir() / "outputs-symlink"));
  EXPECT_FALSE(std::filesystem::exists(farm.dir() / "outputs-hardlink"));
  // The first server still serves.
  EXPECT_NE(farm.submit({kTiny, "--spp", "2"}), 0u);
  if (HasFailure()) farm.dump_logs();
}

TEST(HousekeepingE2E, DeleteFinishedAndCancelledJobsOnly) {
  FarmCluster farm("delete");
  farm.start_server();
  // A queued job (no worker yet) cannot be deleted; an unknown id exits 1.
  const uint64_t queued = farm.submit({kTiny, "--spp", "4"});
  CommandResult r = farm.cli({"delete", std::to_string(queued)});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("job " + std::to_string(queued) + " is queued: cancel it first"),
            std::string::npos)
      << r.err;
  r = farm.cli({"delete", "999999"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("999999"), std::string::npos) << r.err;

  farm.start_worker();
  const v1::JobInfo done = farm.wait_final(queued);
  ASSERT_EQ(done.state(), v1::JOB_STATE_DONE) << done.error();
  ASSERT_TRUE(std::filesystem::exists(done.output_exr()));
  r = farm.cli({"delete", std::to_string(queued)});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "job " + std::to_string(queued) + " deleted\n");
  EXPECT_FALSE(std::filesystem::exists(done.output_exr()));
  EXPECT_FALSE(std::filesystem::exists(done.output_png()));
  EXPECT_EQ(farm.cli({"status", std::to_string(queued)}).exit_code, 1);
  EXPECT_EQ(farm.cli({"delete", std::to_string(queued)}).exit_code, 1);  // gone

  // A cancelled job can be deleted.
  const uint64_t big = farm.submit({kTiny, "--spp", "10000000", "--batch", "100000"});
  ASSERT_EQ(farm.cli({"cancel", std::to_string(big)}).exit_code, 0);
  r = farm.cli({"delete", std::to_string(big), "--json"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out).at("deleted"), true);
  if (HasFailure()) farm.dump_logs();
}

TEST(HousekeepingE2E, AJobOverTheUnitCapIsRefusedWithOneLine) {
  FarmCluster farm("max-units");
  farm.start_server();
  const CommandResult r = farm.cli({"submit", kTiny, "--width", "32", "--height", "32", "--spp",
                                    "2147483647"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err,
            "tessera: job has 2097162 work units (1 tiles x 2097162 batches), over the farm's "
            "limit of 1000000 (server flag --max-units): use fewer spp, a larger --tile or "
            "--batch\n");
  EXPECT_EQ(farm.cli({"list", "--json"}).out.find("\"id\""), std::string::npos);
}

// One unit of one pixel's 2^31 samples per batch: its worker could not be stopped short of
// SIGKILL, so --max-unit-samples refuses it at submit.
TEST(HousekeepingE2E, AJobOverTheUnitSampleCapIsRefusedWithOneLine) {
  FarmCluster farm("max-unit-samples");
  farm.start_server();
  const CommandResult r = farm.cli({"submit", kTiny, "--spp", "2147483647", "--batch",
                                    "2147483647", "--width", "32", "--height", "32"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err,
            "tessera: a work unit of this job has 2199023254528 samples (32 x 32 tile pixels x "
            "2147483647 samples per pixel per batch), over the farm's limit of 268435456 (server "
            "flag --max-unit-samples): use a smaller --batch or --tile\n");
  EXPECT_EQ(farm.cli({"list", "--json"}).out.find("\"id\""), std::string::npos);
}

// Under a raised cap the same kind of unit is leased; cancelling the job stops its render in
// the middle of the pixels' samples (the worker logs the unit dropped), and the idle worker then
// stops on one SIGTERM. Before the sample loop polled the cancellation, neither happened.
TEST(HousekeepingE2E, ACancelledJobStopsAWorkerInTheMiddleOfAHugeBatch) {
  FarmCluster farm("cancel-in-batch");
  farm.start_server({"--lease-seconds", "2", "--max-unit-samples", "1099511627776"});
  const size_t worker = farm.start_worker({"--threads", "2"});
  const uint64_t id = farm.submit({kTiny, "--spp", "2147483647", "--batch", "2147483647",
                                   "--width", "8", "--height", "8"});
  ASSERT_NE(id, 0u);
  farm.wait_job(
      id, [](const v1::JobInfo& j) { return j.counters().units_leased() >= 1; }, "a lease");
  ASSERT_EQ(farm.cli({"cancel", std::to_string(id)}).exit_code, 0);
  const std::filesystem::path log = farm.dir() / ("worker-" + std::to_string(worker) + ".log");
  const auto give_up = std::chrono::steady_clock::now() + kPatience;
  std::string text;
  while ((text = read_text(log)).find("unit dropped") == std::string::npos &&
         std::chrono::steady_clock::now() < give_up) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_NE(text.find("job " + std::to_string(id) + ": lease gone"), std::string::npos) << text;
  farm.worker(worker).signal(SIGTERM);
  EXPECT_EQ(farm.worker(worker).wait_for(kPatience), 0);
  EXPECT_EQ(farm.job(id).counters().samples_merged(), 0u);
}

// Lazy units: under a raised cap a 2147483647-spp job (2,097,162 units) is accepted
// and its submit writes one tile's rows, no unit; a `list` answers with it queued, and a cancel
// and a delete of it succeed.
TEST(HousekeepingE2E, AHugeJobWritesRowsPerTileNotPerUnit) {
  FarmCluster farm("lazy-units");
  farm.start_server({"--max-units", "4194304"});
  const uint64_t id = farm.submit({kTiny, "--width", "32", "--height", "32", "--spp", "2147483647"});
  ASSERT_NE(id, 0u);
  const CommandResult list = farm.cli({"list", "--json"});
  EXPECT_EQ(list.exit_code, 0) << list.err;
  EXPECT_NE(list.out.find("\"id\":" + std::to_string(id)), std::string::npos) << list.out;
  {
    server::Database db(farm.db_path().string());
    auto q = db.prepare(
        "SELECT (SELECT units_total FROM jobs WHERE id = ?1),"
        " (SELECT COUNT(*) FROM tiles WHERE job_id = ?1),"
        " (SELECT COUNT(*) FROM tile_queue WHERE job_id = ?1),"
        " (SELECT COUNT(*) FROM units WHERE job_id = ?1)");
    q->bind(1, int64_t(id));
    ASSERT_TRUE(q->step());
    EXPECT_EQ(q->int64(0), 2097162);
    EXPECT_EQ(q->int64(1), 1);
    EXPECT_EQ(q->int64(2), 1);
    EXPECT_EQ(q->int64(3), 0);
  }
  EXPECT_EQ(farm.cli({"cancel", std::to_string(id)}).exit_code, 0);
  EXPECT_EQ(farm.cli({"delete", std::to_string(id)}).exit_code, 0);
  if (HasFailure()) farm.dump_logs();
}

}  // namespace
}  // namespace tessera::e2e
