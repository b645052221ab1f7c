// Time as the farm sees it: injected everywhere leases and timestamps are decided, so tests
// drive expiry with a fake clock instead of sleeping.
#pragma once

#include <chrono>
#include <cstdint>

namespace tessera::server {

class Clock {
 public:
  virtual ~Clock() = default;
  /// Milliseconds since the Unix epoch.
  virtual int64_t now_unix_ms() const = 0;
};

/// The wall clock (system_clock): lease expiries are compared with timestamps stored in the
/// database, which must stay meaningful across server restarts.
class SystemClock final : public Clock {
 public:
  int64_t now_unix_ms() const override {
    return std::chrono::duration_cast<std::chrono::milliseconds>(
               std::chrono::system_clock::now().time_since_epoch())
        .count();
  }
};

}  // namespace tessera::server
