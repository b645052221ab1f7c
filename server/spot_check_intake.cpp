// ResultIntake's side of spot checks (server/spot_checks.h): a call's results routed through
// SpotChecks (merged now, held, compared, or dropped for a quarantined worker); new quarantines
// stored, the quarantined worker's tiles in unfinished jobs started again (store/tile_redo.h)
// and the leases let go handed back to the queue, all before anything of the call merges; then
// the results the checks release merged like any other.
#include <iostream>
#include <set>

#include "result_intake.h"
#include "store/quarantine_table.h"
#include "store/tile_redo.h"

namespace tessera::server {

std::vector<AcceptOutcome> ResultIntake::upload_checked(
    const std::vector<UnitResult>& results, std::vector<Accumulation>& decoded,
    std::chrono::steady_clock::time_point received) {
  LeaseBook& book = store_.book();
  const SpotChecks::Context context{
      [&book](int64_t job_id) { return book.verify_rate(job_id); },
      [&book](const UnitResult& r) { return book.describe(r.worker_id, r.lease_id); }};
  SpotChecks::Routing routing = store_.checks().route(results, decoded, context);
  for (const std::string& lease_id : routing.hold) book.hold(lease_id);
  // Quarantines first: their tiles start again before anything of this call can end a job.
  apply_checks(routing);
  std::vector<TileMerger::Upload> uploads;
  for (const size_t i : routing.merge) uploads.push_back({&results[i], &decoded[i]});
  std::vector<AcceptOutcome> out(results.size());
  std::exception_ptr error;
  try {
    if (!uploads.empty()) {
      const std::vector<AcceptOutcome> merged = commit_and_answer(uploads, received);
      for (size_t k = 0; k < merged.size(); ++k) out[routing.merge[k]] = merged[k];
    }
  } catch (...) {
    error = std::current_exception();  // after the released results, which are not the call's
  }
  merge_released(routing.released, received);
  if (error) std::rethrow_exception(error);
  for (const auto& [i, answer] : routing.answers) out[i] = answer;
  return out;
}

void ResultIntake::merge_released(std::vector<HeldResult>& released,
                                  std::chrono::steady_clock::time_point received) {
  if (released.empty()) return;
  std::vector<TileMerger::Upload> uploads;
  for (HeldResult& h : released) uploads.push_back({&h.result, &h.decoded});
  try {
    commit_and_answer(uploads, received);
  } catch (const std::exception& e) {
    // Their leases are held (never due): hand them back so the units are rendered again.
    std::cerr << "tessera-server: results released by spot checks not merged (" << e.what()
              << "); their units go back to the queue\n";
    SpotChecks::Routing back;
    for (const HeldResult& h : released) {
      back.requeue.emplace_back(h.result.worker_id, h.result.lease_id);
    }
    apply_checks(back);
  }
}

void ResultIntake::apply_checks(const SpotChecks::Routing& routing) {
  if (!routing.quarantined.empty() || !routing.requeue.empty()) {
    LeaseBook& book = store_.book();
    std::set<int64_t> jobs;
    FarmStore::Lock lock(store_);
    std::vector<std::pair<int64_t, std::string>> requeue = routing.requeue;
    for (const auto& [worker_id, named] : routing.quarantined) {
      const auto& [name, found] = named;
      QuarantineTable table(store_.db());
      Quarantine quarantine = found;
      quarantine.finished_jobs = table.finished_jobs_of(name);
      table.put(name, quarantine);
      store_.checks().note_finished_jobs(name, quarantine.finished_jobs);
      std::string finished;
      for (const int64_t id : quarantine.finished_jobs) finished += " " + std::to_string(id);
      std::cerr << "tessera-server: worker " << worker_id << " (" << name
                << ") quarantined: " << quarantine.reason << "; finished jobs with its results:"
                << (finished.empty() ? " none" : finished) << "\n";
      for (const Lease& l : book.leases_of(worker_id)) requeue.emplace_back(worker_id, l.lease_id);
    }
    for (const auto& [worker_id, named] : routing.quarantined) {
      for (const int64_t job_id : redo_tiles_of(named.first)) jobs.insert(job_id);
    }
    for (const auto& [worker_id, lease_id] : requeue) {
      const std::optional<Lease> lease = book.find(worker_id, lease_id);
      store_.leases().release(worker_id, lease_id, ReleaseReason::shutdown, "quarantined");
      book.ended(lease_id);
      if (lease) jobs.insert(lease->job_id);
    }
    for (const int64_t job_id : jobs) store_.reload_job(job_id);
  }
  if (routing.wake || !routing.requeue.empty() || !routing.quarantined.empty()) {
    events_.notify(true);
  }
}

std::set<int64_t> ResultIntake::redo_tiles_of(const std::string& worker_name) {
  const std::vector<std::pair<int64_t, uint32_t>> tiles =
      tiles_delivered_by(store_.db(), worker_name);
  std::set<int64_t> jobs;
  if (tiles.empty()) return jobs;
  Transaction tx(store_.db());
  for (const auto& [job_id, tile] : tiles) {
    redo_tile(store_.db(), job_id, tile);
    jobs.insert(job_id);
  }
  tx.commit();
  std::string named;
  for (const int64_t job_id : jobs) {
    forget_job(job_id);  // its decoded tiles and waiting results in memory are stale
    named += " " + std::to_string(job_id);
  }
  std::cerr << "tessera-server: " << tiles.size() << " tile(s) with results of " << worker_name
            << " start again from zero, in job(s)" << named << "\n";
  return jobs;
}

void ResultIntake::sweep_checks() {
  LeaseBook& book = store_.book();
  SpotChecks::Routing routing =
      store_.checks().sweep([&book](int64_t job_id) { return book.has_job(job_id); });
  apply_checks(routing);
  merge_released(routing.released, std::chrono::steady_clock::now());
}

}  // namespace tessera::server
