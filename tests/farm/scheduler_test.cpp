// The scheduling order (priority, then age, then batch, then tile) and idempotent leasing.
#include <gtest/gtest.h>

#include <set>

#include "store_fixture.h"

namespace tessera::server {
namespace {

using testing::StoreFixture;

TEST(Scheduler, NoWorkIsANormalAnswer) {
  StoreFixture f;
  EXPECT_EQ(f.scheduler.lease_next(f.make_worker()), std::nullopt);
}

TEST(Scheduler, HigherPriorityFirstThenOlderFirst) {
  StoreFixture f;
  const int64_t old_low = f.make_job(8, 8, 8, 1, 1, /*priority=*/0);
  f.clock.advance(10);
  const int64_t new_high = f.make_job(8, 8, 8, 1, 1, /*priority=*/5);
  f.clock.advance(10);
  const int64_t newer_high = f.make_job(8, 8, 8, 1, 1, /*priority=*/5);
  std::vector<int64_t> order;
  for (int i = 0; i < 3; ++i) order.push_back(f.scheduler.lease_next(f.make_worker())->job_id);
  EXPECT_EQ(order, (std::vector<int64_t>{new_high, newer_high, old_low}));
}

TEST(Scheduler, WithinAJobBatchThenTile) {
  StoreFixture f;
  const int64_t job = f.make_job(16, 8, 8, 3, 1);  // 2 tiles x 3 batches
  std::vector<std::pair<uint32_t, uint32_t>> order;  // (batch, tile)
  for (int i = 0; i < 6; ++i) {
    const Lease l = *f.scheduler.lease_next(f.make_worker());
    EXPECT_EQ(l.job_id, job);
    order.emplace_back(l.batch, l.tile);
  }
  EXPECT_EQ(order, (std::vector<std::pair<uint32_t, uint32_t>>{
                       {0, 0}, {0, 1}, {1, 0}, {1, 1}, {2, 0}, {2, 1}}));
  EXPECT_EQ(f.scheduler.lease_next(f.make_worker()), std::nullopt);
}

TEST(Scheduler, AskingTwiceGivesTheSameLease) {
  StoreFixture f;
  f.make_job(16, 16, 8, 4, 1);
  const int64_t w = f.make_worker();
  const Lease first = *f.scheduler.lease_next(w);
  f.clock.advance(1000);
  const Lease second = *f.scheduler.lease_next(w);
  EXPECT_EQ(second.lease_id, first.lease_id);
  EXPECT_EQ(second.unit_id, first.unit_id);
  // Asking again counts as a sign of life: the expiry moves on.
  EXPECT_EQ(second.expires_unix_ms, f.clock.now_unix_ms() + StoreFixture::kLeaseMs);
  // Another worker gets another unit.
  const Lease other = *f.scheduler.lease_next(f.make_worker("other"));
  EXPECT_NE(other.unit_id, first.unit_id);
  auto q = f.db.prepare("SELECT COUNT(*) FROM units WHERE state = 'leased'");
  ASSERT_TRUE(q->step());
  EXPECT_EQ(q->int64(0), 2);
}

// A unit back in the queue (its lease expired) keeps its row; it goes before the units not yet
// created when it comes first in (batch, tile) order, and none is leased twice.
TEST(Scheduler, AUnitBackInTheQueueGoesInItsBatchOrder) {
  StoreFixture f;
  f.make_job(16, 8, 8, 3, 1);  // 2 tiles x 3 batches
  const int64_t early = f.make_worker("early");
  const Lease first = *f.scheduler.lease_next(early);  // (0, 0)
  f.clock.advance(StoreFixture::kLeaseMs / 2);
  std::vector<std::pair<uint32_t, uint32_t>> order;
  std::vector<int64_t> held;
  for (int i = 0; i < 2; ++i) {  // (0, 1), (1, 0)
    held.push_back(f.make_worker());
    const Lease l = *f.scheduler.lease_next(held.back());
    order.emplace_back(l.batch, l.tile);
  }
  f.clock.advance(StoreFixture::kLeaseMs / 2 + 1);
  ASSERT_EQ(f.leases.expire_due(), 1);  // first's lease only
  while (const std::optional<Lease> l = f.scheduler.lease_next(f.make_worker())) {
    order.emplace_back(l->batch, l->tile);
    if (l->batch == 0 && l->tile == 0) {
      EXPECT_EQ(l->unit_id, first.unit_id);  // the same unit, a new lease
      EXPECT_NE(l->lease_id, first.lease_id);
    }
  }
  EXPECT_EQ(order, (std::vector<std::pair<uint32_t, uint32_t>>{
                       {0, 1}, {1, 0}, {0, 0}, {1, 1}, {2, 0}, {2, 1}}));
}

TEST(Scheduler, StartsTheJobOnItsFirstLease) {
  StoreFixture f;
  const int64_t job = f.make_job(16, 16, 8, 4, 1);
  EXPECT_EQ(f.jobs.get(job)->state, JobState::queued);
  EXPECT_EQ(f.jobs.get(job)->started_unix_ms, 0);
  f.clock.advance(123);
  ASSERT_TRUE(f.scheduler.lease_next(f.make_worker()));
  EXPECT_EQ(f.jobs.get(job)->state, JobState::running);
  EXPECT_EQ(f.jobs.get(job)->started_unix_ms, f.clock.now_unix_ms());
  EXPECT_EQ(f.jobs.get(job)->counters.units_leased, 1u);
}

TEST(Scheduler, SkipsCancelledJobs) {
  StoreFixture f;
  const int64_t first = f.make_job(8, 8, 8, 1, 1, 9);
  const int64_t second = f.make_job(8, 8, 8, 1, 1, 0);
  f.jobs.cancel(first, 0);
  EXPECT_EQ(f.scheduler.lease_next(f.make_worker())->job_id, second);
}

TEST(Scheduler, EveryUnitLeasedExactlyOnce) {
  StoreFixture f;
  f.make_job(40, 24, 8, 5, 2);  // 5 x 3 tiles, 3 batches
  std::set<std::pair<uint32_t, uint32_t>> seen;
  for (;;) {
    const std::optional<Lease> l = f.scheduler.lease_next(f.make_worker());
    if (!l) break;
    EXPECT_TRUE(seen.emplace(l->tile, l->batch).second);
  }
  EXPECT_EQ(seen.size(), 45u);
}

}  // namespace
}  // namespace tessera::server
