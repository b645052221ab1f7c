// The clock a local render's time rule and its progress bar read: steady_clock, or a test's.
#pragma once

#include <chrono>
#include <functional>

namespace tessera {

/// Returns the time now; empty: std::chrono::steady_clock::now. May be called from several
/// threads at once (the render threads' cancellation polls). Tests inject a fake one.
using SteadyClockSource = std::function<std::chrono::steady_clock::time_point()>;

/// `clock`, or steady_clock::now when it is empty.
inline SteadyClockSource or_steady_clock(SteadyClockSource clock) {
  return clock ? std::move(clock) : SteadyClockSource(std::chrono::steady_clock::now);
}

}  // namespace tessera
