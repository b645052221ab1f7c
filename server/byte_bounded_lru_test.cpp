#include "byte_bounded_lru.h"

#include <gtest/gtest.h>

#include <string>

namespace tessera::server {
namespace {

using Lru = ByteBoundedLru<std::pair<int, int>, std::string>;

TEST(ByteBoundedLru, TakeRemovesAndReturnsTheEntry) {
  Lru lru(100);
  lru.put({1, 0}, "a", 10);
  EXPECT_EQ(lru.entries(), 1u);
  EXPECT_EQ(lru.bytes(), 10u);
  EXPECT_EQ(lru.take({1, 1}), std::nullopt);
  EXPECT_EQ(lru.take({1, 0}), "a");
  EXPECT_EQ(lru.take({1, 0}), std::nullopt);  // taken out
  EXPECT_EQ(lru.entries(), 0u);
  EXPECT_EQ(lru.bytes(), 0u);
}

TEST(ByteBoundedLru, ThePutBeyondTheBudgetEvictsTheLeastRecentlyStored) {
  Lru lru(30);
  lru.put({1, 0}, "a", 10);
  lru.put({1, 1}, "b", 10);
  lru.put({1, 2}, "c", 10);
  lru.put({1, 0}, "a2", 10);  // replaces: {1,0} is now the newest
  EXPECT_EQ(lru.entries(), 3u);
  EXPECT_EQ(lru.bytes(), 30u);
  lru.put({2, 0}, "d", 10);  // over: the oldest, {1,1}, goes
  EXPECT_EQ(lru.take({1, 1}), std::nullopt);
  EXPECT_EQ(lru.take({1, 0}), "a2");
  EXPECT_EQ(lru.bytes(), 20u);
  lru.put({3, 0}, "huge", 31);  // alone over the budget: everything goes, itself too
  EXPECT_EQ(lru.entries(), 0u);
  EXPECT_EQ(lru.bytes(), 0u);
}

TEST(ByteBoundedLru, EraseFromRemovesOneContiguousRangeOfKeys) {
  Lru lru(1000);
  for (int job = 1; job <= 3; ++job) {
    for (int tile = 0; tile < 4; ++tile) lru.put({job, tile}, "x", 5);
  }
  lru.erase_from({2, 0}, [](const std::pair<int, int>& k) { return k.first == 2; });
  EXPECT_EQ(lru.entries(), 8u);
  EXPECT_EQ(lru.bytes(), 40u);
  for (int tile = 0; tile < 4; ++tile) {
    EXPECT_EQ(lru.take({2, tile}), std::nullopt);
    EXPECT_EQ(lru.take({1, tile}), "x");
    EXPECT_EQ(lru.take({3, tile}), "x");
  }
}

}  // namespace
}  // namespace tessera::server
