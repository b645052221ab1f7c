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
  /// The unit it holds a lease on, if any.
  std::optional<int64_t> job_id;
  uint32_t tile = 0, batch = 0;
};

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
