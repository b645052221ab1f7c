// A worker that stops says so (Deregister): it is offline at once, not three lease periods
// later; calling again brings it back.
#include <gtest/gtest.h>

#include "coordinator.h"
#include "fake_clock.h"

namespace tessera::server {
namespace {

TEST(Deregister, AStoppedWorkerIsOfflineAtOnceAndOnlineAgainWhenItCalls) {
  testing::FakeClock clock;
  CoordinatorConfig config;
  config.db_path = ":memory:";
  Coordinator farm(config, clock);
  const int64_t id = farm.register_worker({"w", 1, "avx2", "test"});
  const int64_t other = farm.register_worker({"v", 1, "avx2", "test"});
  auto online = [&](int64_t worker) {
    for (const WorkerRecord& w : farm.workers()) {
      if (w.id == worker) return farm.online(w);
    }
    return false;
  };
  ASSERT_TRUE(online(id));
  farm.deregister(id);
  EXPECT_FALSE(online(id));
  EXPECT_TRUE(online(other));
  // It comes back (a new process would register; the same one calling again is online).
  EXPECT_FALSE(farm.lease(id, std::chrono::milliseconds(0), [] { return false; }).has_value());
  EXPECT_TRUE(online(id));
}

// A worker stopped while its long poll waits on the server: the poll's next round must not
// bring it back online (found by hand: `tessera workers` listed a SIGTERM-ed worker online for
// three lease periods, because the waiting LeaseUnit touched it again after Deregister).
TEST(Deregister, ALongPollBegunBeforeDeregisterDoesNotBringTheWorkerBack) {
  testing::FakeClock clock;
  CoordinatorConfig config;
  config.db_path = ":memory:";
  Coordinator farm(config, clock);
  const int64_t id = farm.register_worker({"w", 1, "avx2", "test"});
  auto online = [&] {
    for (const WorkerRecord& w : farm.workers()) {
      if (w.id == id) return farm.online(w);
    }
    return false;
  };
  // The poll finds no work; between its rounds the worker deregisters (the Deregister call
  // arrives while the poll still waits), then the poll runs one more round and ends.
  int rounds = 0;
  auto between_rounds = [&] {
    if (++rounds == 1) farm.deregister(id);
    return rounds >= 2;
  };
  EXPECT_TRUE(farm.lease_units(id, 4, std::chrono::seconds(30), between_rounds).empty());
  EXPECT_EQ(rounds, 2);
  EXPECT_FALSE(online());
  // A call begun afterwards is the worker calling again.
  EXPECT_TRUE(farm.lease_units(id, 4, std::chrono::milliseconds(0), [] { return false; }).empty());
  EXPECT_TRUE(online());
}

}  // namespace
}  // namespace tessera::server
