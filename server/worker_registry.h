// Workers known to the farm: registration, last-seen times, and what each is doing.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "store/sqlite.h"

namespace tessera::server {

struct WorkerRegistration {
  std::string name;
  uint32_t threads = 0;
  std::string isa;
  std::string version;
};

struct WorkerRecord {
  int64_t id = 0;
  WorkerRegistration info;
  int64_t registered_unix_ms = 0;
  int64_t last_seen_unix_ms = 0;
  uint64_t units_done = 0;
  uint64_t units_lost = 0;
  uint64_t samples_returned = 0;  ///< pixel samples in its accepted results, dropped ones included
  uint64_t nan_dropped = 0, inf_dropped = 0;
  /// Filled by the coordinator from its policy: empty when healthy (see health_warning()).
  std::string health_warning;
  /// The unit it holds a lease on, if any (the oldest of its leases when it holds several).
  std::optional<int64_t> job_id;
  uint32_t tile = 0, batch = 0;
};

/// Empty when the worker's NaN/Inf samples are at most `report_fraction` of the samples it
/// returned (or when it returned fewer than kMinSamplesToJudge); otherwise one line for people.
std::string health_warning(const WorkerRecord& worker, double report_fraction);
inline constexpr uint64_t kMinSamplesToJudge = 10'000;

class WorkerRegistry {
 public:
  explicit WorkerRegistry(Database& db) : db_(db) {}

  /// Stores a new worker; returns its id (1, 2, ...).
  int64_t register_worker(const WorkerRegistration& info, int64_t now_unix_ms);
  /// Records that the worker called. Returns false when the id is unknown.
  bool touch(int64_t worker_id, int64_t now_unix_ms);
  std::optional<WorkerRecord> get(int64_t worker_id);
  /// Most recently seen first.
  std::vector<WorkerRecord> list();

 private:
  Database& db_;
};

}  // namespace tessera::server
