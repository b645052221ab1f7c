#include "store/merge_ledger.h"

#include "store/job_contributors_table.h"
#include "store/jobs_table.h"
#include "store/workers_table.h"

namespace tessera::server {

void MergeLedger::delivered(int64_t worker_id, uint64_t samples, uint64_t nan, uint64_t inf) {
  Delivered& d = delivered_[worker_id];
  ++d.units;
  d.samples += samples + nan + inf;
  d.nan += nan;
  d.inf += inf;
}

void MergeLedger::accepted(int64_t job_id, const MergedCounts& merged) {
  Accepted& a = accepted_[job_id];
  ++a.units;
  a.merged.results += merged.results;
  a.merged.pixel_samples += merged.pixel_samples;
  a.merged.nan += merged.nan;
  a.merged.inf += merged.inf;
}

void MergeLedger::write(Database& db, const std::set<Contributor>& known) const {
  for (const Contributor& c : contributors_) {
    if (!known.contains(c)) JobContributorsTable(db).add(c.job_id, c.isa, c.worker_id);
  }
  for (const auto& [worker_id, d] : delivered_) {
    WorkersTable(db).count_delivered(worker_id, d.units, d.samples, d.nan, d.inf);
  }
  for (const auto& [job_id, a] : accepted_) JobsTable(db).count_accepted(job_id, a.units, a.merged);
}

}  // namespace tessera::server
