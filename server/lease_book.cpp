#include "lease_book.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "accum/guide_tile.h"
#include "call_trace.h"
#include "store/jobs_table.h"

namespace tessera::server {

std::optional<LeaseBookJob> load_lease_book_job(Database& db, JobStore& jobs, int64_t job_id) {
  const std::optional<JobRecord> record = jobs.get(job_id);
  if (!record || (record->state != JobState::queued && record->state != JobState::running)) {
    return std::nullopt;
  }
  std::optional<JobSpec> spec = jobs.spec(job_id);
  if (!spec) return std::nullopt;
  LeaseBookJob job;
  job.job_id = job_id;
  job.state = record->state;
  job.priority = record->priority;
  job.submitted_unix_ms = record->submitted_unix_ms;
  job.started_unix_ms = record->started_unix_ms;
  job.spec = std::move(*spec);
  job.tiles = TilesTable(db).positions(job_id);
  job.queue = TileQueue(db).rows(job_id);
  job.units = UnitsTable(db).live(job_id);
  job.failures = FailuresTable(db).of_job(job_id);
  job.any_build = record->any_build;
  job.pinned_build = record->pinned_build;
  job.verify_rate = record->verify_rate;
  return job;
}

LeaseBook::LeaseBook(const Clock& clock, int64_t lease_ms, IdSource new_id)
    : clock_(clock), lease_ms_(lease_ms), new_id_(std::move(new_id)) {}

void LeaseBook::set_health_policy(const WorkerHealthPolicy& policy) {
  std::lock_guard lock(mu_);
  scheduler_.set_block_policy(policy.failures_to_block, policy.forgive_ms);
}

void LeaseBook::add_worker(int64_t worker_id, const std::string& build) {
  std::lock_guard lock(mu_);
  workers_[worker_id] = build;
  scheduler_.set_worker_build(worker_id, build);
}

bool LeaseBook::knows_worker(int64_t worker_id) {
  std::lock_guard lock(mu_);
  return workers_.contains(worker_id);
}

void LeaseBook::touch(int64_t worker_id, int64_t now_unix_ms) {
  std::lock_guard lock(mu_);
  int64_t& t = touches_[worker_id];
  t = std::max(t, now_unix_ms);
}

std::map<int64_t, int64_t> LeaseBook::take_touches() {
  std::lock_guard lock(mu_);
  return std::exchange(touches_, {});
}

void LeaseBook::add_lease(const Lease& lease) {
  leases_[lease.lease_id] = lease;
  if (!held_.contains(lease.lease_id)) {
    by_worker_[lease.worker_id].push_back(lease.lease_id);
    by_expiry_.insert({lease.expires_unix_ms, lease.lease_id});
  }
  if (const auto j = jobs_.find(lease.job_id); j != jobs_.end()) {
    j->second.leased[{lease.tile, lease.batch}] = lease.lease_id;
  }
}

void LeaseBook::remove_lease(const std::string& lease_id) {
  const auto it = leases_.find(lease_id);
  if (it == leases_.end()) return;
  const Lease& l = it->second;
  by_expiry_.erase({l.expires_unix_ms, l.lease_id});
  if (const auto w = by_worker_.find(l.worker_id); w != by_worker_.end()) {
    std::erase(w->second, lease_id);
    if (w->second.empty()) by_worker_.erase(w);
  }
  if (const auto j = jobs_.find(l.job_id); j != jobs_.end()) {
    const auto k = j->second.leased.find({l.tile, l.batch});
    if (k != j->second.leased.end() && k->second == lease_id) j->second.leased.erase(k);
  }
  leases_.erase(it);
}

void LeaseBook::put_job(LeaseBookJob in) {
  std::lock_guard lock(mu_);
  // Expiries moved by heartbeats are the book's alone (the store keeps the granted one).
  std::map<std::string, int64_t> extended;
  if (const auto old = jobs_.find(in.job_id); old != jobs_.end()) {
    for (const auto& [key, id] : old->second.leased) {
      if (const auto l = leases_.find(id); l != leases_.end()) {
        extended[id] = l->second.expires_unix_ms;
      }
    }
    for (const auto& [key, id] : std::map(old->second.leased)) remove_lease(id);
    jobs_.erase(old);
  }
  scheduler_.drop_job(in.job_id);
  if (in.state != JobState::queued && in.state != JobState::running) return;
  Scheduler::Job policy;
  policy.id = in.job_id;
  policy.priority = in.priority;
  policy.submitted_unix_ms = in.submitted_unix_ms;
  policy.running = in.state == JobState::running;
  policy.started_unix_ms = policy.running ? in.started_unix_ms : 0;
  policy.noise = in.spec.options.rule == StopRule::noise;
  policy.any_build = in.any_build;
  policy.build = in.pinned_build;
  if (in.spec.options.rule == StopRule::time) {
    policy.time_budget_ms = std::llround(in.spec.options.time_budget_s * 1000.0);
  }
  Job job;
  job.verify_rate = in.verify_rate;
  job.spec = std::move(in.spec);
  job.plan = job.spec.options.plan();
  policy.tiles.resize(in.tiles.size());
  for (size_t t = 0; t < in.tiles.size(); ++t) {
    job.rects.push_back(in.tiles[t].rect);
    policy.tiles[t].next_batch = in.tiles[t].next_batch;
  }
  for (const TileQueueRow& q : in.queue) {
    if (q.tile >= policy.tiles.size()) continue;
    policy.tiles[q.tile].next_lease = q.next_lease;
    policy.tiles[q.tile].lease_end = q.lease_end;
  }
  for (const JobWorkerFailures& f : in.failures) {
    policy.failures[f.worker_id] = {f.failures, f.last_failure_unix_ms};
  }
  for (const LiveUnit& u : in.units) {
    if (!u.lease) policy.requeued.push_back({u.batch, u.tile, u.unit_id});
  }
  scheduler_.put_job(policy);
  jobs_.emplace(in.job_id, std::move(job));
  for (const LiveUnit& u : in.units) {
    if (!u.lease) continue;
    Lease l = *u.lease;
    if (const auto e = extended.find(l.lease_id); e != extended.end()) {
      l.expires_unix_ms = std::max(l.expires_unix_ms, e->second);
    }
    add_lease(l);
  }
  // The leases granted since the store was read: again, when the store's state still has their
  // unit leasable (they are written by the next flush); otherwise void.
  for (auto g = journal_.begin(); g != journal_.end();) {
    if (g->lease.job_id != in.job_id) {
      ++g;
      continue;
    }
    const Lease& l = g->lease;
    const Scheduler::Pick unit{l.job_id, l.tile, l.batch, g->unborn ? 0 : l.unit_id, g->unborn};
    if (!scheduler_.take(unit, g->at_unix_ms, g->build)) {
      ++voided_;
      g = journal_.erase(g);
      continue;
    }
    Lease kept = l;
    if (const auto e = extended.find(l.lease_id); e != extended.end()) {
      kept.expires_unix_ms = std::max(kept.expires_unix_ms, e->second);
    }
    add_lease(kept);
    ++g;
  }
}

bool LeaseBook::has_job(int64_t job_id) {
  std::lock_guard lock(mu_);
  return jobs_.contains(job_id);
}

void LeaseBook::drop_job(int64_t job_id) {
  std::lock_guard lock(mu_);
  scheduler_.drop_job(job_id);
  const auto it = jobs_.find(job_id);
  if (it == jobs_.end()) return;
  for (const auto& [key, id] : std::map(it->second.leased)) {
    remove_lease(id);
    held_.erase(id);
  }
  jobs_.erase(it);
}

void LeaseBook::set_priority(int64_t job_id, int priority) {
  std::lock_guard lock(mu_);
  scheduler_.set_priority(job_id, priority);
}

void LeaseBook::tile_merged(int64_t job_id, uint32_t tile, uint32_t next_batch, bool closed) {
  std::lock_guard lock(mu_);
  scheduler_.tile_merged(job_id, tile, next_batch, closed);
  const auto it = jobs_.find(job_id);
  if (!closed || it == jobs_.end()) return;
  // The store skipped the tile's queued and leased units and closed its unborn ones
  // (TileMerger::close_tile); leases granted since its flush are void when written.
  Job& job = it->second;
  std::vector<std::string> ids;
  for (auto l = job.leased.lower_bound({tile, 0}); l != job.leased.end() && l->first.first == tile;
       ++l) {
    ids.push_back(l->second);
  }
  for (const std::string& id : ids) remove_lease(id);
}

LeasedUnit LeaseBook::leased_unit(const Job& job, const Lease& lease) const {
  LeasedUnit unit{lease, job.rects[lease.tile], job.plan.batch_begin(lease.batch),
                  job.plan.batch_end(lease.batch), job.spec.options, job.spec.bundle_sha256};
  if (job.spec.guides && unit.sample_begin < kGuideSamples) {
    unit.guide_sample_end = std::min(unit.sample_end, kGuideSamples);
  }
  return unit;
}

std::vector<LeasedUnit> LeaseBook::lease_up_to(int64_t worker_id, uint32_t max_units,
                                               const std::vector<std::string>& delivering,
                                               uint64_t max_samples) {
  const int64_t asked_ns = call_trace::now_ns();
  std::lock_guard lock(mu_);
  const int64_t got_ns = call_trace::now_ns();
  struct Traced {
    int64_t asked, got;
    ~Traced() { call_trace::record("book", asked, got, call_trace::now_ns() - got); }
  } traced{asked_ns, got_ns};
  const int64_t now = clock_.now_unix_ms();
  std::vector<LeasedUnit> out;
  // Every lease the worker holds, expiry extended: a retried call after a lost reply leases
  // nothing twice.
  if (const auto held = by_worker_.find(worker_id); held != by_worker_.end()) {
    for (const std::string& id : held->second) {
      Lease& l = leases_.at(id);
      const int64_t expires = std::max(l.expires_unix_ms, now + lease_ms_);
      by_expiry_.erase({l.expires_unix_ms, id});
      l.expires_unix_ms = expires;
      by_expiry_.insert({expires, id});
      // (At most 64 names: a scan costs less than a set.)
      if (std::find(delivering.begin(), delivering.end(), id) != delivering.end()) continue;
      if (const auto j = jobs_.find(l.job_id); j != jobs_.end()) {
        out.push_back(leased_unit(j->second, l));
      }
    }
  }
  max_units = std::max(1u, max_units);
  if (out.size() >= max_units) return out;
  Scheduler::SampleBound bound;
  if (max_samples != kNoSampleBound) {
    uint64_t held_samples = 0;
    for (const LeasedUnit& u : out) held_samples += u.samples();
    if (!out.empty() && held_samples >= max_samples) return out;
    bound.max_samples = max_samples - std::min(held_samples, max_samples);
    bound.first_free = out.empty();
    bound.samples_of = [this](const Scheduler::Pick& p) {
      const Job& job = jobs_.at(p.job_id);
      return uint64_t(job.rects[p.tile].pixel_count()) *
             (job.plan.batch_end(p.batch) - job.plan.batch_begin(p.batch));
    };
  }
  const auto known = workers_.find(worker_id);
  const std::string build = known == workers_.end() ? std::string() : known->second;
  for (const Scheduler::Pick& p :
       scheduler_.pick(worker_id, now, max_units - out.size(), bound)) {
    Lease lease;
    lease.lease_id = new_id_();
    lease.unit_id = p.unit_id;
    lease.job_id = p.job_id;
    lease.tile = p.tile;
    lease.batch = p.batch;
    lease.worker_id = worker_id;
    lease.expires_unix_ms = now + lease_ms_;
    add_lease(lease);
    journal_.push_back(Grant{lease, p.unborn, now, build});
    ++granted_;
    out.push_back(leased_unit(jobs_.at(p.job_id), lease));
  }
  return out;
}

std::optional<int64_t> LeaseBook::extend(int64_t worker_id, const std::string& lease_id) {
  std::lock_guard lock(mu_);
  const auto it = leases_.find(lease_id);
  if (it == leases_.end() || it->second.worker_id != worker_id) return std::nullopt;
  Lease& l = it->second;
  if (held_.contains(lease_id)) return clock_.now_unix_ms() + lease_ms_;  // delivered, held
  const int64_t expires = std::max(l.expires_unix_ms, clock_.now_unix_ms() + lease_ms_);
  by_expiry_.erase({l.expires_unix_ms, lease_id});
  l.expires_unix_ms = expires;
  by_expiry_.insert({expires, lease_id});
  return expires;
}

std::optional<Lease> LeaseBook::find(int64_t worker_id, const std::string& lease_id) {
  std::lock_guard lock(mu_);
  const auto it = leases_.find(lease_id);
  if (it == leases_.end() || it->second.worker_id != worker_id) return std::nullopt;
  return it->second;
}

void LeaseBook::ended(const std::string& lease_id) {
  std::lock_guard lock(mu_);
  remove_lease(lease_id);
  held_.erase(lease_id);
}

void LeaseBook::hold(const std::string& lease_id) {
  std::lock_guard lock(mu_);
  const auto it = leases_.find(lease_id);
  if (it == leases_.end() || !held_.insert(lease_id).second) return;
  const Lease& l = it->second;
  by_expiry_.erase({l.expires_unix_ms, lease_id});
  if (const auto w = by_worker_.find(l.worker_id); w != by_worker_.end()) {
    std::erase(w->second, lease_id);
    if (w->second.empty()) by_worker_.erase(w);
  }
}

std::optional<LeasedUnit> LeaseBook::describe(int64_t worker_id, const std::string& lease_id) {
  std::lock_guard lock(mu_);
  const auto it = leases_.find(lease_id);
  if (it == leases_.end() || it->second.worker_id != worker_id) return std::nullopt;
  const auto j = jobs_.find(it->second.job_id);
  if (j == jobs_.end()) return std::nullopt;
  return leased_unit(j->second, it->second);
}

std::vector<Lease> LeaseBook::leases_of(int64_t worker_id) {
  std::lock_guard lock(mu_);
  std::vector<Lease> out;
  if (const auto w = by_worker_.find(worker_id); w != by_worker_.end()) {
    for (const std::string& id : w->second) out.push_back(leases_.at(id));
  }
  return out;
}

double LeaseBook::verify_rate(int64_t job_id) {
  std::lock_guard lock(mu_);
  const auto j = jobs_.find(job_id);
  return j == jobs_.end() ? 0.0 : j->second.verify_rate;
}

std::vector<Lease> LeaseBook::due(int64_t now_unix_ms) {
  std::lock_guard lock(mu_);
  std::vector<Lease> out;
  for (const auto& [expires, id] : by_expiry_) {
    if (expires >= now_unix_ms) break;
    const Lease& l = leases_.at(id);
    if (l.unit_id != 0) out.push_back(l);
  }
  return out;
}

void LeaseBook::requeued(const Lease& lease) {
  std::lock_guard lock(mu_);
  remove_lease(lease.lease_id);
  held_.erase(lease.lease_id);
  scheduler_.requeued(lease.job_id, {lease.batch, lease.tile, lease.unit_id});
}

void LeaseBook::revoke_all() {
  std::lock_guard lock(mu_);
  std::vector<Lease> all;
  for (const auto& [id, l] : leases_) {
    if (l.unit_id != 0) all.push_back(l);
  }
  for (const Lease& l : all) {
    remove_lease(l.lease_id);
    scheduler_.requeued(l.job_id, {l.batch, l.tile, l.unit_id});
  }
}

size_t LeaseBook::leases_held() {
  std::lock_guard lock(mu_);
  return leases_.size();
}

std::map<int64_t, size_t> LeaseBook::held_by_worker() {
  std::lock_guard lock(mu_);
  std::map<int64_t, size_t> out;
  for (const auto& [worker, ids] : by_worker_) out[worker] = ids.size();
  return out;
}

std::vector<LeaseBook::Grant> LeaseBook::take_journal() {
  std::lock_guard lock(mu_);
  return std::exchange(journal_, {});
}

void LeaseBook::restore_journal(std::vector<Grant> grants) {
  std::lock_guard lock(mu_);
  grants.insert(grants.end(), journal_.begin(), journal_.end());
  journal_ = std::move(grants);
}

std::vector<Lease> LeaseBook::recorded(const std::vector<Grant>& grants,
                                       const std::vector<std::optional<int64_t>>& unit_ids) {
  std::lock_guard lock(mu_);
  std::vector<Lease> orphans;
  for (size_t i = 0; i < grants.size() && i < unit_ids.size(); ++i) {
    const std::string& id = grants[i].lease.lease_id;
    if (!unit_ids[i]) {
      ++voided_;
      remove_lease(id);
      continue;
    }
    if (const auto it = leases_.find(id); it != leases_.end()) {
      it->second.unit_id = *unit_ids[i];
    } else {
      orphans.push_back(grants[i].lease);
      orphans.back().unit_id = *unit_ids[i];
    }
  }
  return orphans;
}

namespace {

/// Whether a grant of `job_id` to a worker of `build` may be written (write_grants).
bool grant_admitted(JobsTable& jobs, GrantPins& pins, int64_t job_id, const std::string& build) {
  const JobPin* pin = nullptr;
  if (const auto k = pins.known.find(job_id); k != pins.known.end()) pin = &k->second;
  if (const auto l = pins.learned.find(job_id); !pin && l != pins.learned.end()) pin = &l->second;
  if (!pin) {
    const std::optional<JobPin> read = jobs.pin_build(job_id, build);
    if (!read) return true;  // a deleted job: record_grant refuses its grant as before
    pin = &pins.learned.emplace(job_id, *read).first->second;
  }
  if (pin->admits(build)) return true;
  pins.refused.insert(job_id);
  return false;
}

}  // namespace

std::vector<std::optional<int64_t>> write_grants(Database& db, LeaseTable& leases,
                                                 const std::vector<LeaseBook::Grant>& grants,
                                                 GrantPins* pins) {
  GrantPins local;
  GrantPins& p = pins ? *pins : local;
  std::vector<std::optional<int64_t>> unit_ids;
  unit_ids.reserve(grants.size());
  std::map<int64_t, int64_t> started;  // job -> its first lease written here
  JobsTable jobs(db);
  for (const LeaseBook::Grant& g : grants) {
    // Not expected to refuse (the book pins as it leases): a unit of another build than the job's.
    if (!grant_admitted(jobs, p, g.lease.job_id, g.build)) {
      unit_ids.push_back(std::nullopt);
      continue;
    }
    const std::optional<int64_t> unit = leases.record_grant(g.lease, g.unborn);
    if (!unit && g.unborn) {
      try {
        UnitsTable(db).insert_cancelled(g.lease.job_id, g.lease.tile, g.lease.batch);
      } catch (const SqliteError&) {
        // The job is gone (deleted): its result is refused as an unknown unit's.
      }
    }
    if (unit) started.try_emplace(g.lease.job_id, g.at_unix_ms);
    unit_ids.push_back(unit);
  }
  for (const auto& [job_id, at] : started) jobs.start(job_id, at);  // queued -> running
  return unit_ids;
}

int expire_due_leases(LeaseBook& book, LeaseTable& leases, int64_t now_unix_ms) {
  const std::vector<Lease> due = book.due(now_unix_ms);
  if (due.empty()) return 0;
  const std::vector<Lease> requeued = leases.expire(due);
  for (const Lease& l : requeued) book.requeued(l);
  for (const Lease& l : due) book.ended(l.lease_id);  // not current in the store either
  return int(requeued.size());
}

uint64_t LeaseBook::granted() {
  std::lock_guard lock(mu_);
  return granted_;
}

uint64_t LeaseBook::voided() {
  std::lock_guard lock(mu_);
  return voided_;
}

}  // namespace tessera::server
