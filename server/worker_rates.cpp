#include "worker_rates.h"

#include <algorithm>

namespace tessera::server {

void WorkerRates::set_threads(int64_t worker_id, uint32_t threads) {
  std::lock_guard lock(mu_);
  workers_[worker_id].threads = std::max(1u, threads);
}

void WorkerRates::record(int64_t worker_id, uint64_t samples, uint32_t render_ms) {
  std::lock_guard lock(mu_);
  Measured& m = workers_[worker_id];
  m.samples = m.samples * kKeep + double(samples);
  m.ms = m.ms * kKeep + double(std::max(1u, render_ms));
}

WorkerRates::Rate WorkerRates::of(int64_t worker_id) const {
  std::lock_guard lock(mu_);
  Rate out;
  const auto it = workers_.find(worker_id);
  if (it == workers_.end()) return out;
  out.threads = it->second.threads;
  if (it->second.ms > 0) out.samples_per_s = it->second.samples * 1000.0 / it->second.ms;
  return out;
}

}  // namespace tessera::server
