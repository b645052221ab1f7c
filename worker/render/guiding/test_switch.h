// A sampling structure that a test can switch off, and nothing else can: no flag or environment
// variable reaches it, so every worker of a farm builds the same structures (the determinism
// contract, docs/design.md). Used by SpecularTargets and CausticGuide, whose tests compare the
// image's mean with and without them.
#pragma once

#include <atomic>

namespace tessera {

/// `Owner`'s switch: off while any Off of it lives (on every thread).
template <class Owner>
class TestSwitch {
 public:
  class Off {
   public:
    Off() { count().fetch_add(1); }
    ~Off() { count().fetch_sub(1); }
    Off(const Off&) = delete;
    Off& operator=(const Off&) = delete;
  };
  static bool on() { return count().load(std::memory_order_relaxed) == 0; }

 private:
  static std::atomic<int>& count() {
    static std::atomic<int> live{0};
    return live;
  }
};

}  // namespace tessera
