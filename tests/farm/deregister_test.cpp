// A worker that stops says so (Deregister): it is offline at once, not three lease periods
// later; calling again brings it back (issue 15).
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

}  // namespace
}  // namespace tessera::server
