#include "coordinator.h"

#include <algorithm>
#include <set>

#include "farm_error.h"
#include "store/quarantine_table.h"

namespace tessera::server {

Coordinator::Coordinator(const CoordinatorConfig& config, const Clock& clock)
    : clock_(clock),
      store_(config.db_path, clock_, config.lease_ms, config.health),
      presence_(store_, events_, clock_, config.nan_report_fraction),
      images_(store_, events_, clock_, JobOutput(config.output_dir, config.output_opener),
              [this](int64_t job_id) { intake_.checkpoint_job(job_id); }, config.denoise),
      intake_(store_, presence_, events_, clock_, config.merge_cache_bytes,
              [this](int64_t job_id) { images_.finish_job(job_id); },
              config.before_upload_commit),
      leasing_(store_, presence_, events_, clock_,
               [this](int64_t job_id) { images_.finish_job(job_id); }),
      lifecycle_(store_, events_, clock_, images_, intake_, config.limits,
                 config.retention_days),
      views_(store_, intake_),
      health_(store_, events_, config.db_path) {
  store_.checks().set_wait_ms(config.check_wait_ms);
  if (config.on_store_open) config.on_store_open(store_.db());
}

std::optional<LeasedUnit> Coordinator::lease(int64_t worker_id, std::chrono::milliseconds wait,
                                             const std::function<bool()>& cancelled) {
  std::vector<LeasedUnit> units = lease_units(worker_id, 1, wait, cancelled);
  if (units.empty()) return std::nullopt;
  return std::move(units.front());
}

JobRecord Coordinator::job(int64_t job_id) {
  std::vector<JobRecord> one{lifecycle_.job(job_id)};
  note_waiting_for_build(one);
  note_checks(one);
  return std::move(one.front());
}

JobPage Coordinator::jobs(const JobQuery& query) {
  JobPage page = lifecycle_.jobs(query);
  note_waiting_for_build(page.jobs);
  note_checks(page.jobs);
  return page;
}

void Coordinator::note_waiting_for_build(std::vector<JobRecord>& jobs) {
  const auto pinned_and_active = [](const JobRecord& j) {
    return j.pinned_build && (j.state == JobState::queued || j.state == JobState::running);
  };
  if (std::none_of(jobs.begin(), jobs.end(), pinned_and_active)) return;  // no workers read
  std::set<std::string> online;
  for (const WorkerRecord& w : presence_.workers()) {
    if (presence_.online(w)) online.insert(w.info.version);
  }
  for (JobRecord& j : jobs) {
    j.waiting_for_build = pinned_and_active(j) && !online.contains(*j.pinned_build);
  }
}

void Coordinator::note_checks(std::vector<JobRecord>& jobs) {
  for (JobRecord& j : jobs) {
    if (j.verify_rate <= 0) continue;
    const CheckCounts counts = store_.checks().counts_of_job(j.id);
    j.units_checked = counts.checked;
    j.units_unverified = counts.unverified;
  }
}

std::string Coordinator::release_worker(int64_t worker_id) {
  FarmStore::Lock lock(store_);
  const std::optional<WorkerRecord> worker = store_.workers().get(worker_id);
  if (!worker) {
    throw FarmError(ErrorCode::not_found, "no worker " + std::to_string(worker_id));
  }
  const std::string& name = worker->info.name;
  const bool stored = QuarantineTable(store_.db()).remove(name);
  if (!store_.checks().release(name) && !stored) {
    throw FarmError(ErrorCode::failed_precondition, "worker " + std::to_string(worker_id) +
                                                        " (" + name + ") is not quarantined");
  }
  events_.notify(true);
  return name;
}

StoreCounters Coordinator::store_counters() {
  std::lock_guard lock(store_.mutex());  // no flush: reading the counters runs no statement
  return store_.db().counters();
}

}  // namespace tessera::server
