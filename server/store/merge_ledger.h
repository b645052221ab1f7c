// What one merge transaction adds to the store's counters and to its jobs' contributors: per
// worker, the results it delivered (units, samples, NaN/Inf); per job, the units done and what
// their merges merged; and each (job, worker, ISA) whose result a job accepted. The merger notes
// them as it accepts results, and write() stores them in the same transaction just before it
// commits: one UPDATE per worker and per job and one INSERT per new contributor, not one per
// result, and a crash keeps every count with the results it counts, or neither.
#pragma once

#include <compare>
#include <cstdint>
#include <map>
#include <set>
#include <string>

#include "store/jobs_table.h"
#include "store/sqlite.h"

namespace tessera::server {

class MergeLedger {
 public:
  /// A job's accepted result came from this worker, rendered with this ISA (the image's
  /// provenance: store/job_contributors_table.h).
  struct Contributor {
    int64_t job_id = 0;
    int64_t worker_id = 0;
    std::string isa;
    auto operator<=>(const Contributor&) const = default;
  };

  /// The worker delivered an accepted result: one unit, `samples` pixel samples kept and
  /// `nan` + `inf` dropped.
  void delivered(int64_t worker_id, uint64_t samples, uint64_t nan, uint64_t inf);
  /// The job accepted a result (one unit done) whose merge merged `merged` (all zeros when the
  /// result waits for an earlier batch).
  void accepted(int64_t job_id, const MergedCounts& merged);
  void contributed(Contributor contributor) { contributors_.insert(std::move(contributor)); }

  /// Writes the counts and the contributors not in `known` (rows committed earlier) into the
  /// caller's transaction.
  void write(Database& db, const std::set<Contributor>& known) const;
  /// Every contributor noted, for the caller's set of committed rows once it has committed.
  const std::set<Contributor>& contributors() const { return contributors_; }

 private:
  struct Delivered {
    uint64_t units = 0, samples = 0, nan = 0, inf = 0;
  };
  struct Accepted {
    uint32_t units = 0;
    MergedCounts merged;
  };
  std::map<int64_t, Delivered> delivered_;  ///< by worker id
  std::map<int64_t, Accepted> accepted_;    ///< by job id
  std::set<Contributor> contributors_;
};

}  // namespace tessera::server
