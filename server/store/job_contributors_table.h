// The job_contributors table: the distinct (ISA, renderer version) pairs of the workers whose
// results a job accepted, for the image's provenance. Every statement on it is here.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "store/sqlite.h"

namespace tessera::server {

class JobContributorsTable {
 public:
  explicit JobContributorsTable(Database& db) : db_(db) {}

  /// An accepted result of `worker_id` rendered with `isa`: the pair (isa, the worker's
  /// version) is recorded once per job.
  void add(int64_t job_id, const std::string& isa, int64_t worker_id);
  /// Distinct ISAs of the job, sorted.
  std::vector<std::string> isas(int64_t job_id);
  /// Distinct renderer versions of the job, sorted.
  std::vector<std::string> versions(int64_t job_id);

 private:
  Database& db_;
};

}  // namespace tessera::server
