// Group commit (server/group_commit.h): calls arriving during a commit go together in the
// next one, within the group's weight bound, oldest first; a call alone is committed at once; a
// failed commit fails each call of its group.
// The calls are lined up by waiting for the state (GroupCommit::waiting), never for time.
#include "group_commit.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <future>
#include <stdexcept>
#include <thread>
#include <vector>

namespace tessera::server {
namespace {

struct Call {
  int id = 0;
  int answer = 0;
};

TEST(GroupCommit, ACallAloneIsCommittedAtOnce) {
  std::vector<std::vector<int>> groups;
  GroupCommit<Call> gc([&](const std::vector<Call*>& calls) {
    groups.emplace_back();
    for (Call* c : calls) {
      groups.back().push_back(c->id);
      c->answer = c->id * 10;
    }
  });
  Call a{1}, b{2};
  gc.run(a);
  gc.run(b);
  EXPECT_EQ(a.answer, 10);
  EXPECT_EQ(b.answer, 20);
  EXPECT_EQ(groups, (std::vector<std::vector<int>>{{1}, {2}}));
  EXPECT_EQ(gc.committed(), (std::pair<uint64_t, uint64_t>{2, 2}));
}

TEST(GroupCommit, CallsArrivingDuringACommitShareTheNext) {
  std::promise<void> release, started;
  std::shared_future<void> released = release.get_future().share();
  std::vector<std::vector<int>> groups;  // written by the committing thread only
  GroupCommit<Call> gc([&](const std::vector<Call*>& calls) {
    groups.emplace_back();
    for (Call* c : calls) {
      groups.back().push_back(c->id);
      c->answer = c->id * 10;
    }
    if (groups.size() == 1) {  // the first commit lasts until released
      started.set_value();
      released.wait();
    }
  });
  Call a{1}, b{2}, c{3};
  std::thread first([&] { gc.run(a); });
  started.get_future().wait();  // a is committing
  std::thread second([&] { gc.run(b); });
  std::thread third([&] { gc.run(c); });
  while (gc.waiting() != 2) std::this_thread::yield();
  release.set_value();
  first.join();
  second.join();
  third.join();
  ASSERT_EQ(groups.size(), 2u);
  EXPECT_EQ(groups[0], std::vector<int>{1});
  std::vector<int> together = groups[1];
  std::sort(together.begin(), together.end());
  EXPECT_EQ(together, (std::vector<int>{2, 3}));
  EXPECT_EQ(a.answer + b.answer + c.answer, 60);
  EXPECT_EQ(gc.committed(), (std::pair<uint64_t, uint64_t>{2, 3}));
}

TEST(GroupCommit, AFailedCommitFailsEveryCallOfItsGroupOnly) {
  int commits = 0;
  GroupCommit<Call> gc([&](const std::vector<Call*>& calls) {
    if (++commits == 1) throw std::runtime_error("disk full");
    for (Call* c : calls) c->answer = 1;
  });
  Call a{1}, b{2};
  EXPECT_THROW(gc.run(a), std::runtime_error);
  gc.run(b);  // the next group commits
  EXPECT_EQ(b.answer, 1);
  EXPECT_EQ(a.answer, 0);
}

TEST(GroupCommit, AGroupTakesTheOldestCallsWithinItsWeightBound) {
  std::promise<void> release, started;
  std::shared_future<void> released = release.get_future().share();
  std::vector<std::vector<int>> groups;  // written by the committing thread only
  // Each call weighs its id; a group weighs at most 5, and a heavier call goes alone.
  GroupCommit<Call> gc(
      [&](const std::vector<Call*>& calls) {
        groups.emplace_back();
        for (Call* c : calls) {
          groups.back().push_back(c->id);
          c->answer = c->id * 10;
        }
        if (groups.size() == 1) {  // the first commit lasts until released
          started.set_value();
          released.wait();
        }
      },
      [](const Call& c) { return size_t(c.id); }, 5);
  Call first_call{1}, two{2}, three{3}, four{4}, nine{9};
  std::thread first([&] { gc.run(first_call); });
  started.get_future().wait();
  // Lined up one by one, so their order in the queue is known: 2, 3, 9, 4.
  std::vector<std::thread> queued;
  size_t expected = 0;
  for (Call* c : {&two, &three, &nine, &four}) {
    queued.emplace_back([&gc, c] { gc.run(*c); });
    ++expected;
    while (gc.waiting() != expected) std::this_thread::yield();
  }
  release.set_value();
  first.join();
  for (std::thread& t : queued) t.join();
  // 2 + 3 = 5 fit; 9 is over the bound alone and goes alone; then 4.
  EXPECT_EQ(groups, (std::vector<std::vector<int>>{{1}, {2, 3}, {9}, {4}}));
  EXPECT_EQ(two.answer + three.answer + four.answer + nine.answer, 180);
  EXPECT_EQ(gc.committed(), (std::pair<uint64_t, uint64_t>{4, 5}));
}

}  // namespace
}  // namespace tessera::server
