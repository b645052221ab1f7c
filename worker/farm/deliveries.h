// The farm worker's delivery thread: the results of one LeaseUnit call uploaded while the
// worker leases and renders its next units.
#pragma once

#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "tessera/v1/worker_service.pb.h"

namespace tessera::farm {

/// The results of one call delivered on a thread of its own while the worker leases and renders
/// its next units (docs/farm.md, "Batched calls"): a unit's upload and the server's commit no
/// longer leave the render threads idle between calls (about 1.4 ms a call, 0.85 s of a
/// 25-second job on one machine: BENCHMARKS.md, "The farm's overhead on one job"). One
/// delivery at a time, in call order: start() waits for the one before.
class Deliveries {
 public:
  using Deliver = std::function<void(std::vector<v1::UploadResultRequest>&)>;

  /// The thread starts here: after StopSignal, so it inherits the blocked signals.
  explicit Deliveries(Deliver deliver);
  /// Delivers what was started, then ends the thread.
  ~Deliveries();
  Deliveries(const Deliveries&) = delete;
  Deliveries& operator=(const Deliveries&) = delete;

  /// Waits for the delivery in flight (rethrowing what it threw), then starts `results`'.
  void start(std::vector<v1::UploadResultRequest> results);

  /// Waits for the delivery in flight; rethrows what it threw.
  void wait();

  /// Rethrows what the last delivery threw, if it has ended; does not wait.
  void rethrow_if_failed();

  /// The leases of the results in flight (LeaseUnitRequest.delivering).
  std::vector<std::string> in_flight() const;

 private:
  void rethrow(std::unique_lock<std::mutex>&);

  void run();

  Deliver deliver_;
  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::optional<std::vector<v1::UploadResultRequest>> pending_;  ///< guarded by mu_
  std::vector<std::string> in_flight_;                           ///< guarded by mu_
  bool busy_ = false;                                            ///< guarded by mu_
  bool quit_ = false;                                            ///< guarded by mu_
  std::exception_ptr error_;                                     ///< guarded by mu_
  std::thread thread_;  ///< last: started once the fields above exist
};

}  // namespace tessera::farm
