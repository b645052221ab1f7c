#include "spot_checks.h"

#include <algorithm>
#include <cstring>

namespace tessera::server {
namespace {

/// SplitMix64's finaliser: a well-mixed 64-bit hash of `x`.
uint64_t mix(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

template <typename T>
bool same_vector_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(),
                                                           a.size() * sizeof(T)) == 0);
}

std::string unit_name(int64_t job_id, uint32_t tile, uint32_t batch) {
  return "job " + std::to_string(job_id) + " tile " + std::to_string(tile) + " batch " +
         std::to_string(batch);
}

}  // namespace

SpotChecks::SpotChecks(const Clock& clock, int64_t lease_ms, int64_t wait_ms, IdSource new_id)
    : clock_(clock), lease_ms_(lease_ms), new_id_(std::move(new_id)), wait_ms_(wait_ms) {}

bool SpotChecks::sampled(int64_t job_id, uint32_t tile, uint32_t batch, double rate) {
  if (!(rate > 0)) return false;
  if (rate >= 1) return true;
  const uint64_t h = mix(mix(mix(uint64_t(job_id)) ^ tile) ^ (uint64_t(batch) << 32));
  return double(h >> 11) * 0x1.0p-53 < rate;  // uniform in [0, 1)
}

bool SpotChecks::same_bits(const Accumulation& a, const Accumulation& b) {
  return a.rect == b.rect && a.nan_dropped == b.nan_dropped && a.inf_dropped == b.inf_dropped &&
         same_vector_bits(a.rgb, b.rgb) && same_vector_bits(a.lum2, b.lum2) &&
         same_vector_bits(a.count, b.count);
}

void SpotChecks::set_wait_ms(int64_t wait_ms) {
  std::lock_guard lock(mu_);
  wait_ms_ = wait_ms;
}

// ---- Workers --------------------------------------------------------------------------------

void SpotChecks::add_worker(int64_t worker_id, const std::string& name, const std::string& build) {
  std::lock_guard lock(mu_);
  WorkerState& w = workers_[worker_id];
  w.name = name;
  w.build = build;
  w.seen_unix_ms = std::max(w.seen_unix_ms, clock_.now_unix_ms());
}

void SpotChecks::seen(int64_t worker_id, int64_t now_unix_ms) {
  std::lock_guard lock(mu_);
  if (const auto w = workers_.find(worker_id); w != workers_.end()) {
    w->second.seen_unix_ms = std::max(w->second.seen_unix_ms, now_unix_ms);
  }
}

void SpotChecks::load_quarantines(std::map<std::string, Quarantine> by_name) {
  std::lock_guard lock(mu_);
  quarantines_ = std::move(by_name);
  quarantined_names_ = quarantines_.size();
}

bool SpotChecks::quarantined_locked(int64_t worker_id) const {
  const auto w = workers_.find(worker_id);
  return w != workers_.end() && quarantines_.contains(w->second.name);
}

bool SpotChecks::quarantined(int64_t worker_id) {
  if (quarantined_names_.load() == 0) return false;
  std::lock_guard lock(mu_);
  return quarantined_locked(worker_id);
}

std::optional<Quarantine> SpotChecks::quarantine_of(int64_t worker_id) {
  if (quarantined_names_.load() == 0) return std::nullopt;
  std::lock_guard lock(mu_);
  const auto w = workers_.find(worker_id);
  if (w == workers_.end()) return std::nullopt;
  const auto q = quarantines_.find(w->second.name);
  if (q == quarantines_.end()) return std::nullopt;
  return q->second;
}

void SpotChecks::note_finished_jobs(const std::string& worker_name, std::vector<int64_t> jobs) {
  std::lock_guard lock(mu_);
  if (const auto q = quarantines_.find(worker_name); q != quarantines_.end()) {
    q->second.finished_jobs = std::move(jobs);
  }
}

bool SpotChecks::release(const std::string& worker_name) {
  std::lock_guard lock(mu_);
  const bool had = quarantines_.erase(worker_name) > 0;
  quarantined_names_ = quarantines_.size();
  return had;
}

CheckCounts SpotChecks::counts_of_worker(int64_t worker_id) {
  std::lock_guard lock(mu_);
  const auto w = workers_.find(worker_id);
  return w == workers_.end() ? CheckCounts{} : w->second.counts;
}

CheckCounts SpotChecks::counts_of_job(int64_t job_id) {
  std::lock_guard lock(mu_);
  const auto j = jobs_.find(job_id);
  return j == jobs_.end() ? CheckCounts{} : j->second;
}

CheckCounts SpotChecks::totals() {
  std::lock_guard lock(mu_);
  return totals_;
}

size_t SpotChecks::quarantined_count() { return quarantined_names_.load(); }

size_t SpotChecks::held() {
  std::lock_guard lock(mu_);
  size_t n = checks_.size();
  for (const auto& [key, waiting] : probation_) n += waiting.size();
  return n;
}

bool SpotChecks::online(const WorkerState& w, int64_t now) const {
  return now - w.seen_unix_ms <= 3 * lease_ms_;
}

bool SpotChecks::eligible_exists(const std::string& build, const std::set<int64_t>& excluded,
                                 int64_t now) const {
  for (const auto& [id, w] : workers_) {
    if (!excluded.contains(id) && w.build == build && online(w, now) &&
        !quarantines_.contains(w.name)) {
      return true;
    }
  }
  return false;
}

std::set<int64_t> SpotChecks::workers_of(const Check& check) {
  std::set<int64_t> out;
  for (const Candidate& c : check.results) out.insert(c.worker_id);
  return out;
}

// ---- Results --------------------------------------------------------------------------------

AcceptOutcome SpotChecks::held_outcome(const Accumulation& decoded) {
  AcceptOutcome o;
  o.accepted = true;
  for (uint32_t n : decoded.count) o.samples += n;
  return o;
}

bool SpotChecks::wants(const std::vector<UnitResult>& results,
                       const std::function<double(int64_t)>& rate_of) {
  for (const UnitResult& r : results) {
    if (quarantined(r.worker_id)) return true;
    if (check_leases_out_.load() > 0) {
      std::lock_guard lock(mu_);
      if (check_leases_.contains(r.lease_id)) return true;
    }
    if (rate_of(r.job_id) > 0) return true;
  }
  return false;
}

SpotChecks::Routing SpotChecks::route(const std::vector<UnitResult>& results,
                                      std::vector<Accumulation>& decoded, const Context& context) {
  std::lock_guard lock(mu_);
  Routing out;
  for (size_t i = 0; i < results.size(); ++i) {
    const UnitResult& r = results[i];
    const auto check = check_leases_.find(r.lease_id);
    const bool is_check = check != check_leases_.end();
    if (quarantined_locked(r.worker_id)) {
      AcceptOutcome dropped;
      dropped.reason = "worker " + std::to_string(r.worker_id) +
                       " is quarantined: its results are not used until an operator releases it";
      out.answers[i] = dropped;
      if (is_check) {
        if (const auto c = checks_.find(check->second); c != checks_.end()) c->second.lease.reset();
        check_leases_.erase(check);
        out.wake = true;
      } else {
        out.requeue.emplace_back(r.worker_id, r.lease_id);
      }
    } else if (is_check) {
      out.answers[i] = held_outcome(decoded[i]);
      check_result(r.lease_id, r, decoded[i], out);
    } else {
      route_result(i, r, decoded[i], context, out);
    }
  }
  check_leases_out_ = check_leases_.size();
  open_checks_ = checks_.size();
  return out;
}

void SpotChecks::route_result(size_t i, const UnitResult& r, Accumulation& decoded,
                              const Context& context, Routing& out) {
  const double rate = context.rate_of(r.job_id);
  if (!(rate > 0)) {
    out.merge.push_back(i);
    return;
  }
  const JobWorker jw{r.job_id, r.worker_id};
  if (held_already(r)) {  // the same upload again (its answer was lost): answered the same
    out.answers[i] = held_outcome(decoded);
    return;
  }
  const UnitKey key{r.job_id, r.tile, r.batch};
  const bool sampled_unit = sampled(r.job_id, r.tile, r.batch, rate);
  const auto probation = probation_.find(jw);
  const bool first = probation == probation_.end() && !proven_.contains(jw);
  if ((!first && !sampled_unit && probation == probation_.end()) || checks_.contains(key)) {
    out.merge.push_back(i);
    return;
  }
  const std::optional<LeasedUnit> unit = context.unit_of(r);
  if (!unit) {  // not a current lease: the merger drops it and counts it
    out.merge.push_back(i);
    return;
  }
  const AcceptOutcome answer = held_outcome(decoded);
  if (!sampled_unit && probation != probation_.end()) {
    // Waits for its worker's first check in the job.
    out.hold.push_back(r.lease_id);
    probation->second.push_back(HeldResult{r, std::move(decoded)});
    out.answers[i] = answer;
    return;
  }
  if (!open_check(r, decoded, *unit, first, out)) {
    out.merge.push_back(i);
    // A worker alone of its build tries its first-unit check again at each result (another
    // worker may have come) but counts one unverified first unit, not one per result.
    if (sampled_unit || first_unverified_.insert(jw).second) {
      ++totals_.unverified;
      ++jobs_[r.job_id].unverified;
      ++workers_[r.worker_id].counts.unverified;
    }
    return;
  }
  out.answers[i] = answer;
}

bool SpotChecks::held_already(const UnitResult& r) const {
  if (const auto c = checks_.find({r.job_id, r.tile, r.batch}); c != checks_.end()) {
    return c->second.results.front().held.result.lease_id == r.lease_id;
  }
  const auto p = probation_.find({r.job_id, r.worker_id});
  return p != probation_.end() &&
         std::any_of(p->second.begin(), p->second.end(),
                     [&r](const HeldResult& h) { return h.result.lease_id == r.lease_id; });
}

bool SpotChecks::open_check(const UnitResult& r, Accumulation& decoded, const LeasedUnit& unit,
                            bool probation, Routing& out) {
  const int64_t now = clock_.now_unix_ms();
  const auto w = workers_.find(r.worker_id);
  const std::string build = w == workers_.end() ? std::string() : w->second.build;
  if (!eligible_exists(build, {r.worker_id}, now)) return false;
  Check c;
  c.unit = unit;
  c.build = build;
  c.since_unix_ms = now;
  c.probation = probation;
  c.results.push_back(Candidate{r.worker_id, HeldResult{r, std::move(decoded)}});
  checks_.emplace(UnitKey{r.job_id, r.tile, r.batch}, std::move(c));
  if (probation) probation_[{r.job_id, r.worker_id}];
  out.hold.push_back(r.lease_id);
  out.wake = true;
  return true;
}

void SpotChecks::check_result(const std::string& lease_id, const UnitResult& r,
                              Accumulation& decoded, Routing& out) {
  const UnitKey key = check_leases_.at(lease_id);
  check_leases_.erase(lease_id);
  const auto c = checks_.find(key);
  if (c == checks_.end() || !c->second.lease || c->second.lease->worker_id != r.worker_id) return;
  c->second.lease.reset();
  c->second.results.push_back(Candidate{r.worker_id, HeldResult{r, std::move(decoded)}});
  decide(key, out);
}

void SpotChecks::decide(const UnitKey& key, Routing& out) {
  Check& c = checks_.at(key);
  std::vector<Candidate>& res = c.results;
  std::optional<size_t> truth;
  for (size_t i = 0; i < res.size() && !truth; ++i) {
    for (size_t k = i + 1; k < res.size() && !truth; ++k) {
      if (same_bits(res[i].held.decoded, res[k].held.decoded)) truth = i;
    }
  }
  if (!truth) {
    out.wake = true;  // one more worker decides (or the bounded wait ends it)
    return;
  }
  const auto [job_id, tile, batch] = key;
  ++totals_.checked;
  ++jobs_[job_id].checked;
  std::vector<int64_t> agreed, disagreed;
  for (size_t k = 0; k < res.size(); ++k) {
    WorkerState& w = workers_[res[k].worker_id];
    ++w.counts.checked;
    if (same_bits(res[k].held.decoded, res[*truth].held.decoded)) {
      agreed.push_back(res[k].worker_id);
      continue;
    }
    ++w.counts.mismatches;
    ++totals_.mismatches;
    ++jobs_[job_id].mismatches;
    disagreed.push_back(res[k].worker_id);
  }
  // The unit merges the agreed bits under its first lease (still current in the store).
  HeldResult merged = std::move(res[0].held);
  if (*truth != 0 && !same_bits(merged.decoded, res[*truth].held.decoded)) {
    merged.decoded = std::move(res[*truth].held.decoded);
    merged.result.encoded = std::move(res[*truth].held.result.encoded);
    merged.result.isa = res[*truth].held.result.isa;
  }
  const size_t agreeing = agreed.size();
  checks_.erase(key);
  for (const int64_t worker : disagreed) {
    quarantine(worker, key,
               "its result of " + unit_name(job_id, tile, batch) + " differs from " +
                   std::to_string(agreeing) + " other workers'",
               out);
  }
  release_held(std::move(merged), false, out);
  for (const int64_t worker : agreed) {
    proven_.insert({job_id, worker});
    if (probation_.contains({job_id, worker})) {
      end_probation({job_id, worker}, ProbationEnd::passed, out);
    }
  }
}

void SpotChecks::release_held(HeldResult held, bool unverified, Routing& out) {
  if (unverified) {
    ++totals_.unverified;
    ++jobs_[held.result.job_id].unverified;
    ++workers_[held.result.worker_id].counts.unverified;
  }
  out.released.push_back(std::move(held));
}

void SpotChecks::end_probation(const JobWorker& key, ProbationEnd how, Routing& out) {
  const auto p = probation_.find(key);
  if (p == probation_.end()) return;
  std::vector<HeldResult> waiting = std::move(p->second);
  probation_.erase(p);
  for (HeldResult& h : waiting) {
    if (how == ProbationEnd::failed) {
      out.requeue.emplace_back(h.result.worker_id, h.result.lease_id);
    } else {
      release_held(std::move(h), how == ProbationEnd::timed_out, out);
    }
  }
}

void SpotChecks::quarantine(int64_t worker_id, const UnitKey& unit, const std::string& reason,
                            Routing& out) {
  WorkerState& w = workers_[worker_id];
  if (quarantines_.contains(w.name)) return;
  const auto [job_id, tile, batch] = unit;
  const Quarantine q{job_id, tile, batch, clock_.now_unix_ms(), reason, {}};
  quarantines_.emplace(w.name, q);
  quarantined_names_ = quarantines_.size();
  out.quarantined.push_back({worker_id, {w.name, q}});
  // Its results waiting on a probation, and those held for checks of their own, go back to the
  // queue; its part in other checks is forgotten.
  std::vector<JobWorker> probations;
  for (const auto& [key, waiting] : probation_) {
    if (key.second == worker_id) probations.push_back(key);
  }
  for (const JobWorker& key : probations) end_probation(key, ProbationEnd::failed, out);
  for (auto c = checks_.begin(); c != checks_.end();) {
    Check& check = c->second;
    if (check.lease && check.lease->worker_id == worker_id) {
      check_leases_.erase(check.lease->lease_id);
      check.lease.reset();
    }
    if (check.results.front().worker_id == worker_id) {
      out.requeue.emplace_back(worker_id, check.results.front().held.result.lease_id);
      if (check.lease) check_leases_.erase(check.lease->lease_id);
      c = checks_.erase(c);
      continue;
    }
    std::erase_if(check.results, [worker_id](const Candidate& k) {
      return k.worker_id == worker_id;
    });
    ++c;
  }
}

// ---- Check leases ---------------------------------------------------------------------------

std::optional<LeasedUnit> SpotChecks::lease_check(int64_t worker_id) {
  if (open_checks_.load() == 0) return std::nullopt;
  std::lock_guard lock(mu_);
  const auto w = workers_.find(worker_id);
  if (w == workers_.end() || quarantines_.contains(w->second.name)) return std::nullopt;
  const int64_t now = clock_.now_unix_ms();
  for (auto& [key, c] : checks_) {
    if (c.lease || c.build != w->second.build || workers_of(c).contains(worker_id)) continue;
    Lease l = c.unit.lease;
    l.lease_id = new_id_();
    l.worker_id = worker_id;
    l.expires_unix_ms = now + lease_ms_;
    c.lease = l;
    check_leases_.emplace(l.lease_id, key);
    check_leases_out_ = check_leases_.size();
    LeasedUnit unit = c.unit;
    unit.lease = l;
    return unit;
  }
  return std::nullopt;
}

std::optional<int64_t> SpotChecks::extend(int64_t worker_id, const std::string& lease_id) {
  if (check_leases_out_.load() == 0) return std::nullopt;
  std::lock_guard lock(mu_);
  const auto k = check_leases_.find(lease_id);
  if (k == check_leases_.end()) return std::nullopt;
  const auto c = checks_.find(k->second);
  if (c == checks_.end() || !c->second.lease || c->second.lease->worker_id != worker_id) {
    return std::nullopt;
  }
  Lease& l = *c->second.lease;
  l.expires_unix_ms = std::max(l.expires_unix_ms, clock_.now_unix_ms() + lease_ms_);
  return l.expires_unix_ms;
}

bool SpotChecks::give_back(int64_t worker_id, const std::string& lease_id) {
  if (check_leases_out_.load() == 0) return false;
  std::lock_guard lock(mu_);
  const auto k = check_leases_.find(lease_id);
  if (k == check_leases_.end()) return false;
  const auto c = checks_.find(k->second);
  if (c != checks_.end() && c->second.lease && c->second.lease->worker_id == worker_id) {
    c->second.lease.reset();
  }
  check_leases_.erase(k);
  check_leases_out_ = check_leases_.size();
  return true;
}

SpotChecks::Routing SpotChecks::sweep(const std::function<bool(int64_t job_id)>& live) {
  Routing out;
  if (open_checks_.load() == 0) return out;
  std::lock_guard lock(mu_);
  const int64_t now = clock_.now_unix_ms();
  for (auto c = checks_.begin(); c != checks_.end();) {
    Check& check = c->second;
    if (check.lease && check.lease->expires_unix_ms < now) {
      check_leases_.erase(check.lease->lease_id);
      check.lease.reset();
      out.wake = true;
    }
    const int64_t job_id = std::get<0>(c->first);
    const bool ended = !live(job_id);
    const bool waited = now - check.since_unix_ms >= wait_ms_;
    const bool checkable =
        check.lease || eligible_exists(check.build, workers_of(check), now);
    if (!ended && !waited && checkable) {
      ++c;
      continue;
    }
    if (check.lease) check_leases_.erase(check.lease->lease_id);
    const JobWorker first{job_id, check.results.front().worker_id};
    const bool probation = check.probation;
    HeldResult held = std::move(check.results.front().held);
    c = checks_.erase(c);
    if (ended) {
      probation_.erase(first);  // their leases ended with the job
      continue;
    }
    release_held(std::move(held), true, out);
    if (probation) end_probation(first, ProbationEnd::timed_out, out);
  }
  check_leases_out_ = check_leases_.size();
  open_checks_ = checks_.size();
  return out;
}

}  // namespace tessera::server
