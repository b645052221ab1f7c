// Exponential backoff with jitter for reconnecting to the server.
#pragma once

#include <chrono>
#include <cstdint>
#include <random>

namespace tessera::farm {

class Backoff {
 public:
  Backoff(std::chrono::milliseconds initial = std::chrono::milliseconds(100),
          std::chrono::milliseconds max = std::chrono::milliseconds(5000))
      : initial_(initial), max_(max), next_(initial), rng_(std::random_device{}()) {}

  /// The delay before the next attempt: doubles each call up to `max`, then +-20 % jitter so
  /// that many workers do not reconnect in lockstep.
  std::chrono::milliseconds next() {
    const auto base = next_;
    next_ = std::min(max_, next_ * 2);
    std::uniform_real_distribution<double> jitter(0.8, 1.2);
    return std::chrono::milliseconds(int64_t(double(base.count()) * jitter(rng_)));
  }

  /// After a success: start again from `initial`.
  void reset() { next_ = initial_; }

 private:
  std::chrono::milliseconds initial_, max_, next_;
  std::mt19937 rng_;
};

}  // namespace tessera::farm
