// The worker's reconnect backoff on a fake clock (workers once resumed 13 s after a server outage
// ended). However long the outage, the first attempt after it ends comes within the 2 s cap.
#include <gtest/gtest.h>

#include <chrono>

#include "backoff.h"

namespace tessera::farm {
namespace {

using std::chrono::milliseconds;

TEST(Backoff, DoublesFrom100MsAndNeverWaitsMoreThan2s) {
  Backoff backoff(Backoff::kInitial, Backoff::kMax, 7);
  milliseconds step = Backoff::kInitial;
  for (int i = 0; i < 40; ++i) {
    const milliseconds d = backoff.next();
    EXPECT_GE(d.count(), int64_t(0.8 * double(step.count())) - 1) << "attempt " << i;
    EXPECT_LE(d, step) << "attempt " << i;
    EXPECT_LE(d, Backoff::kMax);
    step = std::min(Backoff::kMax, step * 2);
  }
  backoff.reset();
  EXPECT_LE(backoff.next(), Backoff::kInitial);
}

TEST(Backoff, AWorkerResumesWithin2sOfTheEndOfAnOutage) {
  for (const int64_t outage_ms : {50, 900, 3000, 13000, 60000, 600000}) {
    for (uint64_t seed = 1; seed <= 20; ++seed) {
      int64_t now_ms = 1'700'000'000'000;  // the fake clock: moved by hand, by each wait
      Backoff backoff(Backoff::kInitial, Backoff::kMax, seed);
      // Attempts fail while the server is down; the first one at or after its return succeeds.
      const int64_t start = now_ms;
      while (now_ms - start < outage_ms) now_ms += backoff.next().count();
      const int64_t idle_after_outage = now_ms - start - outage_ms;
      EXPECT_LE(idle_after_outage, 2000) << "outage " << outage_ms << " ms, seed " << seed;
    }
  }
}

}  // namespace
}  // namespace tessera::farm
