// Exponential backoff with jitter for reconnecting to the server.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <random>

namespace tessera::farm {

/// Delays between attempts to reach the server: 100 ms doubling up to a cap of 2 s, each drawn
/// in [80 %, 100 %] of its step so that many workers do not retry in lockstep. The cap bounds how
/// long a worker stays idle after the server comes back: at most 2 s after the outage ends
/// (backoff_test.cpp, on a fake clock).
class Backoff {
 public:
  static constexpr std::chrono::milliseconds kInitial{100};
  static constexpr std::chrono::milliseconds kMax{2000};

  /// `seed`: the jitter's; tests fix it, workers draw one from the system.
  explicit Backoff(std::chrono::milliseconds initial = kInitial,
                   std::chrono::milliseconds max = kMax,
                   uint64_t seed = std::random_device{}())
      : initial_(initial), max_(max), next_(initial), rng_(seed) {}

  /// The delay before the next attempt: the step doubles each call up to `max`; the delay is in
  /// [0.8, 1.0] x the step, so never above `max`.
  std::chrono::milliseconds next() {
    const auto step = next_;
    next_ = std::min(max_, next_ * 2);
    std::uniform_real_distribution<double> jitter(0.8, 1.0);
    return std::chrono::milliseconds(int64_t(double(step.count()) * jitter(rng_)));
  }

  /// After a success: start again from `initial`.
  void reset() { next_ = initial_; }

 private:
  std::chrono::milliseconds initial_, max_, next_;
  std::mt19937_64 rng_;
};

}  // namespace tessera::farm
