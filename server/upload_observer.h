// What the coordinator tells an observer about each answered upload: the interface through which
// it feeds counters it does not keep in the store (the dashboard's rates and merge latency,
// server/dashboard/farm_metrics.h), so the coordinator depends on no dashboard code.
#pragma once

#include <cstdint>

namespace tessera::server {

class UploadObserver {
 public:
  virtual ~UploadObserver() = default;

  /// One result answered: `accepted` (merged or waiting for its predecessors) or dropped (stale
  /// lease). `samples` are the pixel samples it carried (sum of per-pixel counts); `merge_s` the
  /// time from receiving the call to its commit, lock wait included. Called from gRPC threads,
  /// outside the coordinator's lock: implementations are thread-safe.
  virtual void record_result(int64_t worker_id, int64_t job_id, bool accepted, uint64_t samples,
                             double merge_s) = 0;
};

}  // namespace tessera::server
