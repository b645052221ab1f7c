// The store lock's two lanes (server/priority_mutex.h): a lease or heartbeat (Urgent) waiting
// for the lock goes before an upload group (Deferring) that waits too, whichever came first, so
// a lease queues behind at most the work in progress. Calls are lined up by waiting for the
// mutex's counters, never for time.
#include "priority_mutex.h"

#include <gtest/gtest.h>

#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace tessera::server {
namespace {

TEST(PriorityMutex, AnUrgentCallerGoesBeforeADeferringOneThatWaitedLonger) {
  // Repeated: without the urgent lane the deferring caller, first in line, would take the
  // mutex first (the kernel wakes the mutex's waiters in order), so the order is checked often.
  for (int round = 0; round < 50; ++round) {
    PriorityMutex m;
    std::vector<std::string> order;  // appended under the mutex
    std::unique_lock held(m);         // the work in progress
    std::thread upload([&] {
      PriorityMutex::Deferring lock(m);
      order.push_back("upload");
    });
    while (m.deferring_waiting() != 1) std::this_thread::yield();
    std::thread lease([&] {
      PriorityMutex::Urgent lock(m);
      order.push_back("lease");
    });
    while (m.urgent_waiting() != 1) std::this_thread::yield();
    held.unlock();
    lease.join();
    upload.join();
    ASSERT_EQ(order, (std::vector<std::string>{"lease", "upload"})) << "round " << round;
  }
}

TEST(PriorityMutex, ADeferringHolderThatYieldsLetsTheWaitingUrgentCallerGoFirst) {
  // An upload group yields between two calls (ResultIntake::commit_uploads): a lease waiting
  // then runs before the group's next transaction, not after the whole group.
  for (int round = 0; round < 50; ++round) {
    PriorityMutex m;
    std::vector<std::string> order;  // appended under the mutex
    std::optional<PriorityMutex::Deferring> group(std::in_place, m);
    order.push_back("upload 1");
    std::thread lease([&] {
      PriorityMutex::Urgent lock(m);
      order.push_back("lease");
    });
    while (m.urgent_waiting() != 1) std::this_thread::yield();
    group->yield();
    order.push_back("upload 2");
    group.reset();
    lease.join();
    ASSERT_EQ(order, (std::vector<std::string>{"upload 1", "lease", "upload 2"})) << "round "
                                                                                   << round;
  }
  PriorityMutex m;
  PriorityMutex::Deferring alone(m);
  alone.yield();  // nobody waits: it keeps going at once
  EXPECT_EQ(m.deferring_waiting(), 0);
}

TEST(PriorityMutex, ADeferringCallerProceedsWhenNoUrgentOneWaits) {
  PriorityMutex m;
  int value = 0;
  {
    PriorityMutex::Deferring lock(m);
    value = 1;
  }
  {
    PriorityMutex::Urgent lock(m);
    value += 1;
  }
  {
    std::lock_guard plain(m);  // every other call takes it plainly
    value += 1;
  }
  {
    PriorityMutex::Deferring again(m);  // not left waiting by the urgent call that has ended
    value += 1;
  }
  EXPECT_EQ(value, 4);
  EXPECT_EQ(m.urgent_waiting(), 0);
  EXPECT_EQ(m.deferring_waiting(), 0);
}

// A plain caller (GetJob, submit, the dashboard) waits for at most K deferring grants (upload
// groups' transactions), however many groups queue back to back. Counted: the group yields
// (a new grant each time) until the plain caller has had the mutex.
TEST(PriorityMutex, APlainCallerWaitsForAtMostKDeferringGrants) {
  for (const int k : {1, 3}) {
    // Repeated: std::mutex alone lets the holder that unlocks and locks again win most times.
    for (int round = 0; round < 20; ++round) {
      PriorityMutex m(k);
      std::optional<PriorityMutex::Deferring> group(std::in_place, m);
      int grants = 0;      // deferring grants since the plain caller began to wait (under m)
      int seen = -1;       // `grants` when the plain caller got the mutex (under m)
      std::thread plain([&] {
        std::lock_guard lock(m);
        seen = grants;
      });
      while (m.plain_waiting() != 1) std::this_thread::yield();
      for (int i = 0; i < 1000 && seen < 0; ++i) {
        group->yield();  // back to back, as a stream of upload groups
        if (seen < 0) ++grants;
      }
      group.reset();
      plain.join();
      ASSERT_GE(seen, 0) << "K " << k << ", round " << round << ": starved for 1000 grants";
      ASSERT_LE(seen, k) << "K " << k << ", round " << round;
    }
  }
}

}  // namespace
}  // namespace tessera::server
