#include "leasing.h"

#include <algorithm>
#include <cmath>

#include "call_trace.h"
#include "farm_error.h"

namespace tessera::server {

uint64_t lease_sample_budget(const WorkerRates::Rate& rate) {
  if (!rate.samples_per_s) return kUnmeasuredSamples * std::max(1u, rate.threads);
  const double samples = *rate.samples_per_s * double(kLeaseSpanMs) / 1000.0;
  if (!(samples > 0)) return 0;  // (NaN too) at least one unit all the same
  if (samples >= 1.8e19) return LeaseBook::kNoSampleBound - 1;
  return uint64_t(std::floor(samples));
}

std::vector<LeasedUnit> Leasing::lease_units(int64_t worker_id, uint32_t max_units,
                                             std::chrono::milliseconds wait,
                                             const std::function<bool()>& cancelled,
                                             const std::vector<std::string>& delivering) {
  if (delivering.size() > kMaxDelivering) {
    throw invalid_argument("a lease names " + std::to_string(delivering.size()) +
                           " leases as delivering; at most " + std::to_string(kMaxDelivering));
  }
  // From the lease book alone: no store lock, no statement (the grants reach the store with
  // the next store operation: FarmStore::flush_leases).
  const auto deadline = std::chrono::steady_clock::now() + wait;
  const uint64_t call = presence_.begin_call();
  for (;;) {
    if (events_.changes.stopped()) return {};  // shutting down: no new leases
    // Read the version before looking, so a change made while we look wakes the wait below.
    const uint64_t seen = events_.work.version();
    presence_.touch_in_memory(worker_id, call);
    // Read at each look: a result delivered while the call waits moves the budget.
    const uint64_t budget = lease_sample_budget(presence_.rates().of(worker_id));
    std::vector<LeasedUnit> units = lease_with_checks(worker_id, max_units, delivering, budget);
    if (!units.empty()) {
      events_.notify(false);  // progress (the job may have started); no work for others
      return units;
    }
    const auto now = std::chrono::steady_clock::now();
    if (now >= deadline || events_.changes.stopped() || (cancelled && cancelled())) return {};
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - now);
    const int64_t waited_ns = call_trace::now_ns();
    events_.work.wait(seen, std::min(left, std::chrono::milliseconds(250)));
    call_trace::record("poll", waited_ns, call_trace::now_ns());
  }
}

std::vector<LeasedUnit> Leasing::lease_with_checks(int64_t worker_id, uint32_t max_units,
                                                   const std::vector<std::string>& delivering,
                                                   uint64_t budget) {
  // A quarantined worker gets no work; a spot check it may render goes first (a held result
  // waits for it: server/spot_checks.h).
  SpotChecks& checks = store_.checks();
  if (checks.quarantined(worker_id)) return {};
  std::vector<LeasedUnit> units =
      store_.book().lease_up_to(worker_id, std::max(1u, max_units), delivering, budget);
  if (std::optional<LeasedUnit> check = checks.lease_check(worker_id)) {
    units.insert(units.begin(), std::move(*check));
  }
  return units;
}

std::optional<int64_t> Leasing::extend(int64_t worker_id, const std::string& lease_id) {
  std::optional<int64_t> expires = store_.book().extend(worker_id, lease_id);
  if (!expires) expires = store_.checks().extend(worker_id, lease_id);
  return expires;
}

std::optional<int64_t> Leasing::heartbeat(int64_t worker_id, const std::string& lease_id) {
  presence_.touch_in_memory(worker_id, presence_.begin_call());
  return extend(worker_id, lease_id);
}

std::vector<std::optional<int64_t>> Leasing::heartbeat_all(
    int64_t worker_id, const std::vector<std::string>& lease_ids) {
  if (lease_ids.size() > kMaxLeasesPerHeartbeat) {
    throw invalid_argument("a heartbeat names " + std::to_string(lease_ids.size()) +
                           " leases; at most " + std::to_string(kMaxLeasesPerHeartbeat) +
                           " per call");
  }
  presence_.touch_in_memory(worker_id, presence_.begin_call());
  std::vector<std::optional<int64_t>> out;
  out.reserve(lease_ids.size());
  for (const std::string& id : lease_ids) out.push_back(extend(worker_id, id));
  return out;
}

ReleaseOutcome Leasing::release(int64_t worker_id, const std::string& lease_id,
                                ReleaseReason reason, const std::string& message) {
  ReleaseOutcome outcome;
  if (store_.checks().give_back(worker_id, lease_id)) {  // a spot check's: another may take it
    events_.notify(true);
    outcome.released = true;
    return outcome;
  }
  {
    FarmStore::Lock lock(store_);
    presence_.touch_or_throw(worker_id, presence_.begin_call());
    const std::optional<Lease> held = store_.book().find(worker_id, lease_id);
    outcome = store_.leases().release(worker_id, lease_id, reason, message);
    if (held) store_.reload_job(held->job_id);  // its unit queued again, a failure block, or failed
  }
  events_.notify(true);
  return outcome;
}

int Leasing::expire_leases() {
  int expired = 0;
  std::vector<int64_t> out_of_time;
  {
    FarmStore::Lock lock(store_);
    // Expiry is the lease book's (heartbeats extend leases there): its due leases go back to
    // the queue in the store, then in the book.
    expired = expire_due_leases(store_.book(), store_.leases(), clock_.now_unix_ms());
    out_of_time = store_.leases().enforce_time_budgets();
  }
  if (expired > 0) events_.notify(true);
  for (int64_t id : out_of_time) finish_job_(id);
  return expired;
}

}  // namespace tessera::server
