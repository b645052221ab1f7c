// The workers table: every statement on `workers`, one operation per thing that happens to a
// worker (it registers, calls, delivers a result, loses a unit). Reads join the unit it holds a
// lease on (its oldest, by the partial index units_worker).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "store/quarantine_table.h"
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
  /// Filled by the coordinator from the lease book: the leases it holds now.
  uint32_t units_held = 0;
  /// The unit it holds a lease on, if any (the oldest of its leases when it holds several).
  std::optional<int64_t> job_id;
  uint32_t tile = 0, batch = 0;
  /// Filled by the coordinator from its spot checks (server/spot_checks.h): set when the
  /// worker's name is quarantined; checks its results took part in, and mismatches among them.
  std::optional<Quarantine> quarantine;
  uint64_t checks = 0, mismatches = 0;
};

class WorkersTable {
 public:
  explicit WorkersTable(Database& db) : db_(db) {}

  /// A new row; returns the worker's id (1, 2, ...).
  int64_t insert(const WorkerRegistration& info, int64_t now_unix_ms);
  /// last_seen moves to at least `now_unix_ms`. False when the id is unknown.
  bool touch(int64_t worker_id, int64_t now_unix_ms);
  /// `units` accepted results: units_done + units, and their samples (NaN/Inf included) and
  /// NaN/Inf counts.
  void count_delivered(int64_t worker_id, uint64_t units, uint64_t samples, uint64_t nan,
                       uint64_t inf);
  /// A unit the worker lost: its lease expired, or its result came under a superseded lease.
  void count_lost(int64_t worker_id);

  std::optional<WorkerRecord> get(int64_t worker_id);
  /// Workers registered (rows of the table).
  int64_t count();
  /// Most recently seen first.
  std::vector<WorkerRecord> list();

 private:
  Database& db_;
};

}  // namespace tessera::server
