// The worker_quarantines table: workers whose result disagreed with two other workers' in a spot
// check (server/spot_checks.h), by name, so that a quarantine outlives the worker's registration
// and the server's restart. Every statement on the table is here.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "store/sqlite.h"

namespace tessera::server {

/// Why a worker is quarantined: the unit whose check it failed, when, and one line of reason.
struct Quarantine {
  int64_t job_id = 0;
  uint32_t tile = 0, batch = 0;
  int64_t time_unix_ms = 0;
  std::string reason;
  /// Done jobs with results of the worker's name when it was quarantined: their images may hold
  /// its unchecked results.
  std::vector<int64_t> finished_jobs;
  bool operator==(const Quarantine&) const = default;
};

class QuarantineTable {
 public:
  explicit QuarantineTable(Database& db) : db_(db) {}

  /// Quarantines `worker_name` (a quarantine already there is kept: the first reason stands).
  void put(const std::string& worker_name, const Quarantine& quarantine);
  /// Ends the name's quarantine; false when it had none.
  bool remove(const std::string& worker_name);
  /// Every quarantined name.
  std::map<std::string, Quarantine> all();
  /// Done jobs with a unit delivered by a worker of this name, in id order.
  std::vector<int64_t> finished_jobs_of(const std::string& worker_name);

 private:
  Database& db_;
};

}  // namespace tessera::server
