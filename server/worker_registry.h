// Workers known to the farm: registration, last-seen times, and what each is doing (the SQL is
// store/workers_table.h).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "store/sqlite.h"
#include "store/workers_table.h"

namespace tessera::server {

/// Empty when the worker's NaN/Inf samples are at most `report_fraction` of the samples it
/// returned (or when it returned fewer than kMinSamplesToJudge); otherwise one line for people.
std::string health_warning(const WorkerRecord& worker, double report_fraction);
inline constexpr uint64_t kMinSamplesToJudge = 10'000;

class WorkerRegistry {
 public:
  explicit WorkerRegistry(Database& db) : db_(db), table_(db) {}

  /// Stores a new worker; returns its id (1, 2, ...).
  int64_t register_worker(const WorkerRegistration& info, int64_t now_unix_ms);
  /// Records that the worker called. Returns false when the id is unknown.
  bool touch(int64_t worker_id, int64_t now_unix_ms);
  std::optional<WorkerRecord> get(int64_t worker_id);
  /// Most recently seen first.
  std::vector<WorkerRecord> list();

 private:
  Database& db_;
  WorkersTable table_;
};

}  // namespace tessera::server
