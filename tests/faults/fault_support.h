// Shared pieces of the fault-injection suite (docs/reliability.md): the seeded randomness of
// the fault moments, the tiny job every round renders, and the one check every job must pass
// after any fault — done, every unit merged exactly once (counters from `tessera status --json`
// and, independently, the per-pixel sample counts in the store), nothing left pending, and the
// pixels bit-identical to `tessera-worker render` of the same options.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "process.h"

namespace tessera::faults {

/// The seed of a test's fault moments: TESSERA_FAULT_SEED when set (to replay a failure), else
/// a fresh one. Printed, and recorded as the test's "seed" property.
uint64_t fault_seed(const std::string& test);

/// How many rounds a test runs: TESSERA_FAULT_ROUNDS when set, else `fallback`.
int fault_rounds(int fallback);

/// The Cornell box at 32x32 in 4 tiles of 16x16 and many tiny batches (256 spp in batches of
/// 2: 512 units), so that a fault lands mid-job whatever the machine's speed, plus `seed`.
/// batch = 0 gives no --batch: the progressive default (1, 1, 2, ... 128 spp: 36 units).
std::vector<std::string> tiny_job(uint64_t seed, uint32_t spp = 256, uint32_t batch = 2);

std::filesystem::path cornell_scene();

/// Runs a command (the tessera CLI, possibly inside `ip netns exec`) with the given arguments.
using CliRunner = std::function<e2e::CommandResult(const std::vector<std::string>&)>;

/// `tessera status JOB --json`, parsed. Fails the test (and returns null) when it fails.
nlohmann::json cli_status(const CliRunner& cli, uint64_t job_id);

/// What one finished job showed.
struct JobOutcome {
  bool ok = false;
  uint64_t units_total = 0, results_dropped = 0, leases_expired = 0, units_released = 0;
};

/// The check after every fault (see the top of this file): `status` from `tessera status
/// --json`, the job's tiles read from `db`, the final EXR against `tessera-worker render` of the
/// same `options` (rendered into `dir`). Adds gtest failures naming what differs.
JobOutcome verify_job(const nlohmann::json& status, const std::filesystem::path& db,
                      const std::vector<std::string>& options, const std::filesystem::path& dir,
                      const std::string& label);

/// Polls `done` every 25 ms up to `patience`; true when it became true.
bool poll_until(const std::function<bool()>& done, std::chrono::milliseconds patience);

}  // namespace tessera::faults
