#include "fault_support.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <iostream>
#include <thread>

#include "accum/accumulation_codec.h"
#include "farm_cluster.h"
#include "store/sqlite.h"

namespace tessera::faults {

uint64_t fault_seed(const std::string& test) {
  uint64_t seed = 0;
  if (const char* env = std::getenv("TESSERA_FAULT_SEED"); env && *env) {
    seed = std::stoull(env);
  } else {
    std::random_device device;
    seed = (uint64_t(device()) << 32) | device();
  }
  std::cout << "[faults] " << test << ": seed " << seed << " (replay with TESSERA_FAULT_SEED="
            << seed << ")" << std::endl;
  ::testing::Test::RecordProperty("seed", std::to_string(seed));
  return seed;
}

int fault_rounds(int fallback) {
  if (const char* env = std::getenv("TESSERA_FAULT_ROUNDS"); env && *env) {
    return std::max(1, std::atoi(env));
  }
  return fallback;
}

std::filesystem::path cornell_scene() { return e2e::source_dir() / "scenes" / "cornell.json"; }

std::vector<std::string> tiny_job(uint64_t seed, uint32_t spp, uint32_t batch) {
  std::vector<std::string> options = {"--width", "32", "--height", "32", "--tile", "16",
                                      "--spp", std::to_string(spp), "--seed", std::to_string(seed)};
  if (batch > 0) {
    options.push_back("--batch");
    options.push_back(std::to_string(batch));
  }
  return options;
}

nlohmann::json cli_status(const CliRunner& cli, uint64_t job_id) {
  const e2e::CommandResult r = cli({"status", std::to_string(job_id), "--json"});
  EXPECT_EQ(r.exit_code, 0) << "tessera status: " << r.err;
  if (r.exit_code != 0) return nullptr;
  return nlohmann::json::parse(r.out);
}

namespace {

std::filesystem::path local_render(const std::vector<std::string>& options,
                                   const std::filesystem::path& dir) {
  std::string key;
  for (const std::string& o : options) key += o + "_";
  for (char& c : key) {
    if (c == '-') c = 'x';
  }
  const auto path = dir / ("local-" + key + ".exr");
  if (std::filesystem::exists(path)) return path;
  std::vector<std::string> argv = {TESSERA_WORKER_BIN, "render", cornell_scene().string(), "-q",
                                   "--threads", "1", "-o", path.string()};
  argv.insert(argv.end(), options.begin(), options.end());
  const e2e::CommandResult r = e2e::run_command(argv, dir / ("local-" + key), {}, e2e::kPatience);
  EXPECT_EQ(r.exit_code, 0) << "tessera-worker render: " << r.err;
  return path;
}

}  // namespace

JobOutcome verify_job(const nlohmann::json& status, const std::filesystem::path& db,
                      const std::vector<std::string>& options, const std::filesystem::path& dir,
                      const std::string& label) {
  SCOPED_TRACE(label);
  JobOutcome outcome;
  if (status.is_null()) return outcome;
  const auto& c = status.at("counters");
  const uint64_t id = status.at("id").get<uint64_t>();
  const uint32_t spp = status.at("options").at("spp").get<uint32_t>();
  outcome.units_total = c.at("units_total").get<uint64_t>();
  outcome.results_dropped = c.at("results_dropped").get<uint64_t>();
  outcome.leases_expired = c.at("leases_expired").get<uint64_t>();
  outcome.units_released = c.at("units_released").get<uint64_t>();

  // The counters: every unit accepted once and merged once.
  EXPECT_EQ(status.at("state"), "done") << status.at("error");
  EXPECT_EQ(c.at("units_done").get<uint64_t>(), outcome.units_total) << status.dump();
  EXPECT_EQ(c.at("results_merged").get<uint64_t>(), outcome.units_total) << status.dump();
  EXPECT_EQ(c.at("units_leased").get<uint64_t>(), 0u) << status.dump();
  EXPECT_EQ(status.at("spp_merged").get<uint32_t>(), spp) << status.dump();
  EXPECT_EQ(status.at("progress").get<double>(), 1.0);

  // The store, counted another way: every pixel of every tile holds exactly spp samples (a
  // batch lost or merged twice would show here), and the results table is empty: nothing waits
  // and nothing is left outside the checkpoints.
  {
    server::Database store(db.string());
    auto tiles = store.prepare(
        "SELECT t.tile, c.accumulation FROM tiles t LEFT JOIN tile_checkpoints c"
        " ON c.job_id = t.job_id AND c.tile = t.tile WHERE t.job_id = ?");
    tiles->bind(1, int64_t(id));
    int tile_count = 0;
    while (tiles->step()) {
      ++tile_count;
      const Accumulation acc = decode_accumulation(tiles->blob(1));
      size_t wrong = 0;
      for (uint32_t n : acc.count) wrong += (n != spp);
      EXPECT_EQ(wrong, 0u) << "tile " << tiles->int64(0) << ": " << wrong
                           << " pixels do not hold exactly " << spp << " samples";
    }
    EXPECT_GT(tile_count, 0);
    auto left = store.prepare("SELECT COUNT(*) FROM results WHERE job_id = ?");
    left->bind(1, int64_t(id));
    EXPECT_TRUE(left->step());
    EXPECT_EQ(left->int64(0), 0)
        << "results waiting, or merged outside the checkpoints, after the job finished";
  }

  // The determinism contract: the farm's pixels are the local render's, bit for bit.
  const std::filesystem::path exr = status.at("output_exr").get<std::string>();
  const auto local = local_render(options, dir);
  EXPECT_TRUE(e2e::same_pixels(exr, local));
  outcome.ok = !::testing::Test::HasFailure();
  return outcome;
}

bool poll_until(const std::function<bool()>& done, std::chrono::milliseconds patience) {
  const auto deadline = std::chrono::steady_clock::now() + patience;
  while (!done()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(25));
  }
  return true;
}

}  // namespace tessera::faults
