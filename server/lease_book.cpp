#include "lease_book.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "scheduler.h"

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
  return job;
}

LeaseBook::LeaseBook(const Clock& clock, int64_t lease_ms, IdSource new_id)
    : clock_(clock), lease_ms_(lease_ms), new_id_(std::move(new_id)) {}

void LeaseBook::set_health_policy(const WorkerHealthPolicy& policy) {
  std::lock_guard lock(mu_);
  policy_ = policy;
}

void LeaseBook::add_worker(int64_t worker_id) {
  std::lock_guard lock(mu_);
  workers_.insert(worker_id);
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

bool LeaseBook::eligible(const Job& job, uint32_t tile) const {
  const Tile& t = job.tiles[tile];
  if (t.next_lease >= t.lease_end) return false;
  return !job.noise || t.next_lease < t.next_batch + Scheduler::kNoiseLookahead;
}

void LeaseBook::unopen(Job& job, uint32_t tile) { job.open.erase({job.tiles[tile].next_lease, tile}); }

void LeaseBook::reopen(Job& job, uint32_t tile) {
  if (eligible(job, tile)) job.open.insert({job.tiles[tile].next_lease, tile});
}

void LeaseBook::add_lease(const Lease& lease) {
  leases_[lease.lease_id] = lease;
  by_worker_[lease.worker_id].push_back(lease.lease_id);
  by_expiry_.insert({lease.expires_unix_ms, lease.lease_id});
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
    order_.erase(order_key(old->second));
    jobs_.erase(old);
  }
  if (in.state != JobState::queued && in.state != JobState::running) return;
  Job job;
  job.id = in.job_id;
  job.state = in.state;
  job.priority = in.priority;
  job.submitted_unix_ms = in.submitted_unix_ms;
  job.started_unix_ms = in.started_unix_ms;
  job.noise = in.spec.options.rule == StopRule::noise;
  if (in.spec.options.rule == StopRule::time) {
    job.time_budget_ms = std::llround(in.spec.options.time_budget_s * 1000.0);
  }
  job.spec = std::move(in.spec);
  job.plan = job.spec.options.plan();
  job.tiles.resize(in.tiles.size());
  for (size_t t = 0; t < in.tiles.size(); ++t) {
    job.rects.push_back(in.tiles[t].rect);
    job.tiles[t].next_batch = in.tiles[t].next_batch;
  }
  for (const TileQueueRow& q : in.queue) {
    if (q.tile >= job.tiles.size()) continue;
    job.tiles[q.tile].next_lease = q.next_lease;
    job.tiles[q.tile].lease_end = q.lease_end;
  }
  for (const JobWorkerFailures& f : in.failures) {
    job.failures[f.worker_id] = {f.failures, f.last_failure_unix_ms};
  }
  for (uint32_t t = 0; t < job.tiles.size(); ++t) reopen(job, t);
  const auto [it, inserted] = jobs_.emplace(job.id, std::move(job));
  Job& j = it->second;
  for (const LiveUnit& u : in.units) {
    if (!u.lease) {
      j.requeued.insert({u.batch, u.tile, u.unit_id});
      continue;
    }
    Lease l = *u.lease;
    if (const auto e = extended.find(l.lease_id); e != extended.end()) {
      l.expires_unix_ms = std::max(l.expires_unix_ms, e->second);
    }
    add_lease(l);
  }
  // The leases granted since the store was read: again, when the store's state still has their
  // unit leasable (they are written by the next flush); otherwise void.
  for (auto g = journal_.begin(); g != journal_.end();) {
    if (g->lease.job_id != j.id) {
      ++g;
      continue;
    }
    const Lease& l = g->lease;
    bool ok = false;
    if (l.tile < j.tiles.size()) {
      if (g->unborn) {
        Tile& t = j.tiles[l.tile];
        ok = t.next_lease == l.batch && l.batch < t.lease_end;
        if (ok) {
          unopen(j, l.tile);
          ++t.next_lease;
          reopen(j, l.tile);
        }
      } else {
        ok = j.requeued.erase({l.batch, l.tile, l.unit_id}) > 0;
      }
    }
    if (!ok) {
      ++voided_;
      g = journal_.erase(g);
      continue;
    }
    if (j.state == JobState::queued) {
      j.state = JobState::running;
      j.started_unix_ms = g->at_unix_ms;
    }
    Lease kept = l;
    if (const auto e = extended.find(l.lease_id); e != extended.end()) {
      kept.expires_unix_ms = std::max(kept.expires_unix_ms, e->second);
    }
    add_lease(kept);
    ++g;
  }
  order_.insert(order_key(j));
}

void LeaseBook::drop_job(int64_t job_id) {
  std::lock_guard lock(mu_);
  const auto it = jobs_.find(job_id);
  if (it == jobs_.end()) return;
  for (const auto& [key, id] : std::map(it->second.leased)) remove_lease(id);
  order_.erase(order_key(it->second));
  jobs_.erase(it);
}

void LeaseBook::set_priority(int64_t job_id, int priority) {
  std::lock_guard lock(mu_);
  const auto it = jobs_.find(job_id);
  if (it == jobs_.end()) return;
  order_.erase(order_key(it->second));
  it->second.priority = priority;
  order_.insert(order_key(it->second));
}

void LeaseBook::tile_merged(int64_t job_id, uint32_t tile, uint32_t next_batch, bool closed) {
  std::lock_guard lock(mu_);
  const auto it = jobs_.find(job_id);
  if (it == jobs_.end() || tile >= it->second.tiles.size()) return;
  Job& job = it->second;
  Tile& t = job.tiles[tile];
  unopen(job, tile);
  t.next_batch = std::max(t.next_batch, next_batch);
  if (closed) {
    // The store skipped the tile's queued and leased units and closed its unborn ones
    // (TileMerger::close_tile); leases granted since its flush are void when written.
    t.lease_end = std::min(t.lease_end, t.next_lease);
    for (auto r = job.requeued.begin(); r != job.requeued.end();) {
      r = std::get<1>(*r) == tile ? job.requeued.erase(r) : std::next(r);
    }
    std::vector<std::string> ids;
    for (auto l = job.leased.lower_bound({tile, 0});
         l != job.leased.end() && l->first.first == tile; ++l) {
      ids.push_back(l->second);
    }
    for (const std::string& id : ids) remove_lease(id);
  }
  reopen(job, tile);
}

bool LeaseBook::blocked(const Job& job, int64_t worker_id, int64_t now) const {
  const auto f = job.failures.find(worker_id);
  return f != job.failures.end() && f->second.first >= policy_.failures_to_block &&
         f->second.second > now - policy_.forgive_ms;
}

std::optional<Lease> LeaseBook::grant_next(Job& job, int64_t worker_id, int64_t now) {
  // Past its budget a time job gets batch 0 only: every tile gets its first batch.
  const bool over_budget = job.time_budget_ms > 0 && job.started_unix_ms > 0 &&
                           job.started_unix_ms + job.time_budget_ms <= now;
  const uint32_t limit = over_budget ? 1 : std::numeric_limits<uint32_t>::max();
  std::optional<std::tuple<uint32_t, uint32_t, int64_t>> requeued;
  for (const auto& r : job.requeued) {
    const auto [batch, tile, unit_id] = r;
    if (batch >= limit) break;
    if (job.noise && batch >= job.tiles[tile].next_batch + Scheduler::kNoiseLookahead) continue;
    requeued = r;
    break;
  }
  std::optional<std::pair<uint32_t, uint32_t>> unborn;
  if (!job.open.empty() && job.open.begin()->first < limit) unborn = *job.open.begin();
  if (!requeued && !unborn) return std::nullopt;
  // The earlier of the two in (batch, tile) order.
  const bool fresh = unborn && (!requeued || *unborn < std::pair(std::get<0>(*requeued),
                                                                std::get<1>(*requeued)));
  Lease lease;
  lease.lease_id = new_id_();
  lease.job_id = job.id;
  lease.worker_id = worker_id;
  lease.expires_unix_ms = now + lease_ms_;
  if (fresh) {
    lease.batch = unborn->first;
    lease.tile = unborn->second;
    unopen(job, lease.tile);
    ++job.tiles[lease.tile].next_lease;
    reopen(job, lease.tile);
  } else {
    std::tie(lease.batch, lease.tile, lease.unit_id) = *requeued;
    job.requeued.erase(*requeued);
  }
  if (job.state == JobState::queued) {
    // queued -> running on the first lease (written with the journal: JobsTable::start).
    job.state = JobState::running;
    job.started_unix_ms = now;
  }
  add_lease(lease);
  journal_.push_back(Grant{lease, fresh, now});
  ++granted_;
  return lease;
}

LeasedUnit LeaseBook::leased_unit(const Job& job, const Lease& lease) const {
  return LeasedUnit{lease, job.rects[lease.tile], job.plan.batch_begin(lease.batch),
                    job.plan.batch_end(lease.batch), job.spec.options, job.spec.bundle_sha256};
}

std::vector<LeasedUnit> LeaseBook::lease_up_to(int64_t worker_id, uint32_t max_units) {
  std::lock_guard lock(mu_);
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
      if (const auto j = jobs_.find(l.job_id); j != jobs_.end()) {
        out.push_back(leased_unit(j->second, l));
      }
    }
  }
  max_units = std::max(1u, max_units);
  for (const OrderKey& key : order_) {
    if (out.size() >= max_units) break;
    Job& job = jobs_.at(std::get<2>(key));
    if (job.open.empty() && job.requeued.empty()) continue;
    if (blocked(job, worker_id, now)) continue;
    while (out.size() < max_units) {
      const std::optional<Lease> lease = grant_next(job, worker_id, now);
      if (!lease) break;
      out.push_back(leased_unit(job, *lease));
    }
  }
  return out;
}

std::optional<int64_t> LeaseBook::extend(int64_t worker_id, const std::string& lease_id) {
  std::lock_guard lock(mu_);
  const auto it = leases_.find(lease_id);
  if (it == leases_.end() || it->second.worker_id != worker_id) return std::nullopt;
  Lease& l = it->second;
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
  const auto it = jobs_.find(lease.job_id);
  if (it == jobs_.end()) return;
  it->second.requeued.insert({lease.batch, lease.tile, lease.unit_id});
}

void LeaseBook::revoke_all() {
  std::lock_guard lock(mu_);
  std::vector<Lease> all;
  for (const auto& [id, l] : leases_) {
    if (l.unit_id != 0) all.push_back(l);
  }
  for (const Lease& l : all) {
    remove_lease(l.lease_id);
    if (const auto it = jobs_.find(l.job_id); it != jobs_.end()) {
      it->second.requeued.insert({l.batch, l.tile, l.unit_id});
    }
  }
}

size_t LeaseBook::leases_held() {
  std::lock_guard lock(mu_);
  return leases_.size();
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

uint64_t LeaseBook::granted() {
  std::lock_guard lock(mu_);
  return granted_;
}

uint64_t LeaseBook::voided() {
  std::lock_guard lock(mu_);
  return voided_;
}

}  // namespace tessera::server
