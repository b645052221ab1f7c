// The job_clients table: which client submitted each job (the per-client quota,
// --max-queued-jobs). Every statement on it is here.
#pragma once

#include <cstdint>
#include <string>

#include "store/sqlite.h"

namespace tessera::server {

class JobClientsTable {
 public:
  explicit JobClientsTable(Database& db) : db_(db) {}

  /// A submit by `client` (in the submit's transaction or right after it).
  void add(int64_t job_id, const std::string& client);
  /// The client's queued and running jobs.
  uint64_t unfinished_of(const std::string& client);

 private:
  Database& db_;
};

}  // namespace tessera::server
