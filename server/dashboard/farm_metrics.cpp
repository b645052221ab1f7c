#include "dashboard/farm_metrics.h"

#include <algorithm>

namespace tessera::server {

FarmMetrics::FarmMetrics(const Clock& clock)
    : clock_(clock), started_unix_ms_(clock.now_unix_ms()) {}

void FarmMetrics::record_result(int64_t worker_id, int64_t job_id, bool accepted,
                                uint64_t samples, double merge_s) {
  const int64_t now = clock_.now_unix_ms();
  std::lock_guard lock(mu_);
  if (accepted) {
    ++accepted_;
    recent_.push_back({now, worker_id, job_id, samples});
  } else {
    ++dropped_;
  }
  for (size_t i = 0; i < kMergeBuckets.size(); ++i) {
    if (merge_s <= kMergeBuckets[i]) ++merge_.cumulative[i];
  }
  ++merge_.count;
  merge_.sum_s += merge_s;
  prune(now);
}

void FarmMetrics::prune(int64_t now_unix_ms) const {
  while (!recent_.empty() && recent_.front().t_unix_ms <= now_unix_ms - kRateWindowMs) {
    recent_.pop_front();
  }
}

template <typename Match>
double FarmMetrics::rate(Match match, int64_t since_unix_ms) const {
  const int64_t now = clock_.now_unix_ms();
  std::lock_guard lock(mu_);
  prune(now);
  uint64_t samples = 0;
  for (const Event& e : recent_) {
    if (match(e)) samples += e.samples;
  }
  if (samples == 0) return 0.0;
  // The window shrinks to what was observable: since the server (or the job) started.
  const int64_t from = std::max({now - kRateWindowMs, started_unix_ms_, since_unix_ms});
  const double span_s = std::max(1.0, double(now - from) / 1000.0);
  return double(samples) / span_s;
}

double FarmMetrics::farm_samples_per_s() const {
  return rate([](const Event&) { return true; }, 0);
}

double FarmMetrics::worker_samples_per_s(int64_t worker_id) const {
  return rate([&](const Event& e) { return e.worker_id == worker_id; }, 0);
}

double FarmMetrics::job_samples_per_s(int64_t job_id, int64_t since_unix_ms) const {
  return rate([&](const Event& e) { return e.job_id == job_id; }, since_unix_ms);
}

uint64_t FarmMetrics::results_accepted() const {
  std::lock_guard lock(mu_);
  return accepted_;
}

uint64_t FarmMetrics::results_dropped() const {
  std::lock_guard lock(mu_);
  return dropped_;
}

FarmMetrics::MergeHistogram FarmMetrics::merge_latency() const {
  std::lock_guard lock(mu_);
  return merge_;
}

}  // namespace tessera::server
