// Server-wide counters that the store does not keep: the results each worker and job delivered
// over the last seconds (for samples/s), results accepted and dropped since the server started,
// and how long merges take. Recorded by Coordinator::upload, read by the dashboard's /metrics and
// JSON API. Thread-safe; time comes from the injected Clock (rates) and from the caller
// (durations it measured).
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <mutex>

#include "clock.h"
#include "submit_budget.h"
#include "upload_observer.h"

namespace tessera::server {

class FarmMetrics : public UploadObserver {
 public:
  /// Upper bounds (seconds) of the merge-latency histogram buckets; +Inf is implicit.
  static constexpr std::array<double, 11> kMergeBuckets = {0.001, 0.0025, 0.005, 0.01, 0.025, 0.05,
                                                           0.1,   0.25,   0.5,   1.0,  2.5};
  /// Rates are averaged over this window.
  static constexpr int64_t kRateWindowMs = 10'000;

  struct MergeHistogram {
    std::array<uint64_t, kMergeBuckets.size()> cumulative{};  ///< results with latency <= bound
    uint64_t count = 0;                                       ///< every result (the +Inf bucket)
    double sum_s = 0;
  };

  explicit FarmMetrics(const Clock& clock);

  /// One UploadResult answered: `accepted` (merged or waiting for its predecessors) or dropped
  /// (stale lease). `samples` are the pixel samples it carried (sum of per-pixel counts);
  /// `merge_s` the time from receiving it to its commit, lock wait included.
  void record_result(int64_t worker_id, int64_t job_id, bool accepted, uint64_t samples,
                     double merge_s) override;

  /// Pixel samples accepted per second over the last kRateWindowMs (or since `since_unix_ms`
  /// when that is later, e.g. a job's start; at least one second). 0 when nothing arrived.
  double farm_samples_per_s() const;
  double worker_samples_per_s(int64_t worker_id) const;
  double job_samples_per_s(int64_t job_id, int64_t since_unix_ms) const;

  uint64_t results_accepted() const;
  uint64_t results_dropped() const;
  MergeHistogram merge_latency() const;

  /// The submit checks' memory budget shown with the rest (tessera_submit_memory_*); none until
  /// set. It must outlive this object.
  void set_submit_budget(const SubmitBudget* budget) { submit_budget_ = budget; }
  const SubmitBudget* submit_budget() const { return submit_budget_; }

 private:
  const SubmitBudget* submit_budget_ = nullptr;
  struct Event {
    int64_t t_unix_ms;
    int64_t worker_id, job_id;
    uint64_t samples;
  };
  template <typename Match>
  double rate(Match match, int64_t since_unix_ms) const;
  void prune(int64_t now_unix_ms) const;  // requires mu_

  const Clock& clock_;
  const int64_t started_unix_ms_;
  mutable std::mutex mu_;
  mutable std::deque<Event> recent_;  ///< accepted results of the last window, oldest first
  uint64_t accepted_ = 0, dropped_ = 0;
  MergeHistogram merge_;
};

}  // namespace tessera::server
