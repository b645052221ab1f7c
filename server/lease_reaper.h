// The one component that checks lease timeouts (Flamenco's habit): a thread that, every
// `period`, returns the units of expired leases to the queue. The expiry itself is decided by
// LeaseTable against the injected clock, so tests drive it without this thread.
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "coordinator.h"

namespace tessera::server {

class LeaseReaper {
 public:
  LeaseReaper(Coordinator& coordinator, std::chrono::milliseconds period);
  /// Stops and joins the thread.
  ~LeaseReaper();
  LeaseReaper(const LeaseReaper&) = delete;
  LeaseReaper& operator=(const LeaseReaper&) = delete;

 private:
  void run();

  Coordinator& coordinator_;
  std::chrono::milliseconds period_;
  std::mutex mu_;
  std::condition_variable cv_;
  bool stop_ = false;
  std::thread thread_;  ///< last: starts after the members it uses
};

}  // namespace tessera::server
