// A clock the test moves by hand: lease expiry without sleeping.
#pragma once

#include <atomic>
#include <cstdint>

#include "clock.h"

namespace tessera::server::testing {

class FakeClock final : public Clock {
 public:
  explicit FakeClock(int64_t start_unix_ms = 1'700'000'000'000) : now_(start_unix_ms) {}
  int64_t now_unix_ms() const override { return now_.load(); }
  void advance(int64_t ms) { now_ += ms; }

 private:
  std::atomic<int64_t> now_;
};

}  // namespace tessera::server::testing
