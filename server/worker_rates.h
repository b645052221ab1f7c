// How fast each worker renders, measured by the server from the worker's own results: the pixel
// samples of each accepted result over the wall time the worker spent rendering it
// (UploadResultRequest.render_ms), and the render threads it registered with. This is what
// bounds a worker's leases (leasing.h, lease_sample_budget). Kept in memory only: after a server
// start each worker is measured again from its first results.
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <optional>

namespace tessera::server {

class WorkerRates {
 public:
  /// Each result weighs this much less at each later result of the same worker: the rate
  /// follows a worker whose scenes change (a simple scene renders faster than a heavy one)
  /// within a few calls, and one odd result does not swing it.
  static constexpr double kKeep = 0.75;

  /// The worker registered (or was read from the store) with `threads` render threads (0 when
  /// it did not say: counted as 1).
  void set_threads(int64_t worker_id, uint32_t threads);
  /// An accepted result of `samples` pixel samples that the worker rendered in `render_ms`.
  /// A unit renders on all of the worker's threads, so the rate is the whole worker's. 0 ms
  /// (a unit under a millisecond) counts as 1 ms, which can only make the rate lower.
  void record(int64_t worker_id, uint64_t samples, uint32_t render_ms);

  struct Rate {
    /// Samples per second over its recent results (weighted by kKeep), all threads together;
    /// nullopt before its first measured result on this server.
    std::optional<double> samples_per_s;
    uint32_t threads = 1;  ///< render threads, at least 1
  };
  Rate of(int64_t worker_id) const;

 private:
  struct Measured {
    uint32_t threads = 1;
    double samples = 0, ms = 0;  ///< decayed sums (kKeep)
  };
  mutable std::mutex mu_;
  std::map<int64_t, Measured> workers_;  ///< guarded by mu_
};

}  // namespace tessera::server
