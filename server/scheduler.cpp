#include "scheduler.h"

#include <algorithm>
#include <iterator>
#include <limits>

namespace tessera::server {

Scheduler::OrderKey Scheduler::order_key(const Job& j) {
  return {-int64_t{j.priority}, j.submitted_unix_ms, j.id};
}

void Scheduler::set_block_policy(int failures_to_block, int64_t forgive_ms) {
  failures_to_block_ = failures_to_block;
  forgive_ms_ = forgive_ms;
}

bool Scheduler::eligible(const State& s, uint32_t tile) const {
  const Tile& t = s.job.tiles[tile];
  if (t.next_lease >= t.lease_end) return false;
  return !s.job.noise || t.next_lease < t.next_batch + kNoiseLookahead;
}

void Scheduler::unopen(State& s, uint32_t tile) { s.open.erase({s.job.tiles[tile].next_lease, tile}); }

void Scheduler::reopen(State& s, uint32_t tile) {
  if (eligible(s, tile)) s.open.insert({s.job.tiles[tile].next_lease, tile});
}

void Scheduler::lease_unborn(State& s, uint32_t tile) {
  unopen(s, tile);
  ++s.job.tiles[tile].next_lease;
  reopen(s, tile);
}

void Scheduler::put_job(const Job& job) {
  drop_job(job.id);
  State s;
  s.job = job;
  for (const Requeued& r : job.requeued) {
    if (r.tile < job.tiles.size()) s.requeued.insert(r);
  }
  s.job.requeued.clear();
  for (uint32_t t = 0; t < s.job.tiles.size(); ++t) reopen(s, t);
  order_.insert(order_key(s.job));
  jobs_.emplace(job.id, std::move(s));
}

void Scheduler::drop_job(int64_t job_id) {
  const auto it = jobs_.find(job_id);
  if (it == jobs_.end()) return;
  order_.erase(order_key(it->second.job));
  jobs_.erase(it);
}

void Scheduler::set_priority(int64_t job_id, int priority) {
  const auto it = jobs_.find(job_id);
  if (it == jobs_.end()) return;
  order_.erase(order_key(it->second.job));
  it->second.job.priority = priority;
  order_.insert(order_key(it->second.job));
}

void Scheduler::tile_merged(int64_t job_id, uint32_t tile, uint32_t next_batch, bool closed) {
  const auto it = jobs_.find(job_id);
  if (it == jobs_.end() || tile >= it->second.job.tiles.size()) return;
  State& s = it->second;
  Tile& t = s.job.tiles[tile];
  unopen(s, tile);
  t.next_batch = std::max(t.next_batch, next_batch);
  if (closed) {
    t.lease_end = std::min(t.lease_end, t.next_lease);
    for (auto r = s.requeued.begin(); r != s.requeued.end();) {
      r = r->tile == tile ? s.requeued.erase(r) : std::next(r);
    }
  }
  reopen(s, tile);
}

void Scheduler::requeued(int64_t job_id, const Requeued& unit) {
  const auto it = jobs_.find(job_id);
  if (it == jobs_.end() || unit.tile >= it->second.job.tiles.size()) return;
  it->second.requeued.insert(unit);
}

bool Scheduler::blocked(const State& s, int64_t worker_id, int64_t now) const {
  const auto f = s.job.failures.find(worker_id);
  return f != s.job.failures.end() && f->second.first >= failures_to_block_ &&
         f->second.second > now - forgive_ms_;
}

bool Scheduler::admits(const State& s, const std::string& build) {
  return s.job.any_build || !s.job.build || *s.job.build == build;
}

void Scheduler::pin(State& s, const std::string& build) {
  if (!s.job.any_build && !s.job.build) s.job.build = build;
}

void Scheduler::set_worker_build(int64_t worker_id, const std::string& build) {
  worker_builds_[worker_id] = build;
}

std::optional<std::string> Scheduler::pinned_build(int64_t job_id) const {
  const auto it = jobs_.find(job_id);
  return it == jobs_.end() ? std::nullopt : it->second.job.build;
}

void Scheduler::start(State& s, int64_t at) {
  if (s.job.running) return;
  s.job.running = true;  // queued -> running on its first lease (JobsTable::start)
  s.job.started_unix_ms = at;
}

bool Scheduler::next_unit(const State& s, int64_t now, Pick& out) const {
  // Past its budget a time job gets batch 0 only: every tile gets its first batch.
  // (started_unix_ms > 0: as JobsTable::running_over_budget decides it in the store.)
  const bool over_budget = s.job.time_budget_ms > 0 && s.job.running &&
                           s.job.started_unix_ms > 0 &&
                           s.job.started_unix_ms + s.job.time_budget_ms <= now;
  const uint32_t limit = over_budget ? 1 : std::numeric_limits<uint32_t>::max();
  const Requeued* requeued = nullptr;
  for (const Requeued& r : s.requeued) {
    if (r.batch >= limit) break;
    if (s.job.noise && r.batch >= s.job.tiles[r.tile].next_batch + kNoiseLookahead) continue;
    requeued = &r;
    break;
  }
  const std::pair<uint32_t, uint32_t>* unborn = nullptr;
  if (!s.open.empty() && s.open.begin()->first < limit) unborn = &*s.open.begin();
  if (!requeued && !unborn) return false;
  // The earlier of the two in (batch, tile) order.
  const bool fresh =
      unborn && (!requeued || *unborn < std::pair(requeued->batch, requeued->tile));
  out = Pick{};
  out.job_id = s.job.id;
  if (fresh) {
    out.batch = unborn->first;
    out.tile = unborn->second;
    out.unborn = true;
  } else {
    out.batch = requeued->batch;
    out.tile = requeued->tile;
    out.unit_id = requeued->unit_id;
  }
  return true;
}

void Scheduler::take_next(State& s, const Pick& unit, int64_t now) {
  if (unit.unborn) {
    lease_unborn(s, unit.tile);
  } else {
    s.requeued.erase({unit.batch, unit.tile, unit.unit_id});
  }
  start(s, now);
}

std::vector<Scheduler::Pick> Scheduler::pick(int64_t worker_id, int64_t now_unix_ms, size_t n,
                                             const SampleBound& bound) {
  std::vector<Pick> out;
  uint64_t samples = 0;
  static const std::string kNoBuild;
  const auto known = worker_builds_.find(worker_id);
  const std::string& build = known == worker_builds_.end() ? kNoBuild : known->second;
  for (const OrderKey& key : order_) {
    if (out.size() >= n) break;
    State& s = jobs_.at(std::get<2>(key));
    if (s.open.empty() && s.requeued.empty()) continue;
    if (blocked(s, worker_id, now_unix_ms) || !admits(s, build)) continue;
    Pick p;
    while (out.size() < n && next_unit(s, now_unix_ms, p)) {
      if (bound.samples_of) {
        const uint64_t unit = bound.samples_of(p);
        const bool free = out.empty() && bound.first_free;
        // The first unit over the bound ends the call: later jobs' smaller units wait their
        // turn rather than pass a larger one.
        if (!free && (samples + unit > bound.max_samples || samples + unit < samples)) {
          return out;
        }
        samples += unit;
      }
      take_next(s, p, now_unix_ms);
      pin(s, build);  // in the same pick: a worker of another build never gets a unit of it
      out.push_back(p);
    }
  }
  return out;
}

std::vector<Scheduler::Pick> Scheduler::pick(int64_t worker_id, int64_t now_unix_ms, size_t n) {
  return pick(worker_id, now_unix_ms, n, SampleBound{});
}

bool Scheduler::take(const Pick& unit, int64_t at_unix_ms, const std::string& build) {
  const auto it = jobs_.find(unit.job_id);
  if (it == jobs_.end() || unit.tile >= it->second.job.tiles.size()) return false;
  State& s = it->second;
  if (!admits(s, build)) return false;
  if (unit.unborn) {
    const Tile& t = s.job.tiles[unit.tile];
    if (t.next_lease != unit.batch || unit.batch >= t.lease_end) return false;
    lease_unborn(s, unit.tile);
  } else if (s.requeued.erase({unit.batch, unit.tile, unit.unit_id}) == 0) {
    return false;
  }
  start(s, at_unix_ms);
  pin(s, build);
  return true;
}

int64_t Scheduler::started_unix_ms(int64_t job_id) const {
  const auto it = jobs_.find(job_id);
  return it == jobs_.end() ? 0 : it->second.job.started_unix_ms;
}

}  // namespace tessera::server
