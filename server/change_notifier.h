// Wakes whoever waits for the farm to change: WatchJob streams (progress) and workers long-polling
// LeaseUnit (new work). A version counter, so a change between "look" and "wait" is never missed.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>

namespace tessera::server {

class ChangeNotifier {
 public:
  uint64_t version() const {
    std::lock_guard lock(mu_);
    return version_;
  }

  /// Something changed: wake every waiter.
  void notify() {
    {
      std::lock_guard lock(mu_);
      ++version_;
    }
    cv_.notify_all();
  }

  /// Waits until the version differs from `seen`, `timeout` passes, or stop() is called.
  /// Returns the version then.
  uint64_t wait(uint64_t seen, std::chrono::milliseconds timeout) {
    std::unique_lock lock(mu_);
    cv_.wait_for(lock, timeout, [&] { return version_ != seen || stopped_; });
    return version_;
  }

  /// Ends every wait at once, now and later (server shutdown).
  void stop() {
    {
      std::lock_guard lock(mu_);
      stopped_ = true;
    }
    cv_.notify_all();
  }

  bool stopped() const {
    std::lock_guard lock(mu_);
    return stopped_;
  }

 private:
  mutable std::mutex mu_;
  std::condition_variable cv_;
  uint64_t version_ = 0;
  bool stopped_ = false;
};

}  // namespace tessera::server
