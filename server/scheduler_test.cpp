// The scheduling policy (server/scheduler.h): first on its own, SQL-free (priority, age,
// (batch, tile) order, units back in the queue, the time budget, the noise lookahead, blocked
// workers, closed tiles), then through the lease book and the store as the server leases
// (testing::BookLeaser): idempotent leasing, the job's start, every unit leased once.
#include "scheduler.h"

#include <gtest/gtest.h>

#include <limits>
#include <set>

#include "store_fixture.h"

namespace tessera::server {
namespace {

using testing::StoreFixture;

/// A job of `tiles` tiles with `batches` batches each, none leased, none merged.
Scheduler::Job policy_job(int64_t id, uint32_t tiles, uint32_t batches, int priority = 0,
                          int64_t submitted = 0) {
  Scheduler::Job job;
  job.id = id;
  job.priority = priority;
  job.submitted_unix_ms = submitted;
  job.tiles.assign(tiles, Scheduler::Tile{0, batches, 0});
  return job;
}

/// (batch, tile) of each pick.
std::vector<std::pair<uint32_t, uint32_t>> order_of(const std::vector<Scheduler::Pick>& picks) {
  std::vector<std::pair<uint32_t, uint32_t>> out;
  for (const Scheduler::Pick& p : picks) out.emplace_back(p.batch, p.tile);
  return out;
}

using Order = std::vector<std::pair<uint32_t, uint32_t>>;

TEST(SchedulerPolicy, JobsByPriorityThenAgeThenId) {
  Scheduler s;
  s.put_job(policy_job(1, 1, 1, /*priority=*/0, /*submitted=*/0));
  s.put_job(policy_job(2, 1, 1, 5, 20));
  s.put_job(policy_job(3, 1, 1, 5, 10));
  s.put_job(policy_job(4, 1, 1, 5, 10));
  std::vector<int64_t> jobs;
  for (const Scheduler::Pick& p : s.pick(/*worker=*/7, /*now=*/100, 10)) jobs.push_back(p.job_id);
  EXPECT_EQ(jobs, (std::vector<int64_t>{3, 4, 2, 1}));
  EXPECT_TRUE(s.pick(7, 100, 10).empty());
}

TEST(SchedulerPolicy, TheLowestPriorityRunsLastAndTheHighestFirst) {
  // The order negates the priority: in 32 bits INT_MIN's negation overflowed and ran it first.
  Scheduler s;
  s.put_job(policy_job(1, 1, 1, std::numeric_limits<int>::min(), 0));
  s.put_job(policy_job(2, 1, 1, 0, 10));
  s.put_job(policy_job(3, 1, 1, std::numeric_limits<int>::max(), 20));
  std::vector<int64_t> jobs;
  for (const Scheduler::Pick& p : s.pick(/*worker=*/7, /*now=*/100, 10)) jobs.push_back(p.job_id);
  EXPECT_EQ(jobs, (std::vector<int64_t>{3, 2, 1}));
}

// A sample bound (the lease's budget, leasing.h) stops a call at the first unit over it: the
// first unit is free, and a later job's smaller units never pass a larger one.
TEST(SchedulerPolicy, ASampleBoundStopsAtTheFirstUnitOverItAndSkipsNothing) {
  Scheduler s;
  s.put_job(policy_job(1, 4, 1, 0, 0));   // 4 units of 100 samples
  s.put_job(policy_job(2, 4, 1, 0, 10));  // 4 units of 10 samples
  Scheduler::SampleBound bound;
  bound.samples_of = [](const Scheduler::Pick& p) -> uint64_t { return p.job_id == 1 ? 100 : 10; };
  bound.max_samples = 250;
  const std::vector<Scheduler::Pick> first = s.pick(7, 0, 16, bound);
  ASSERT_EQ(first.size(), 2u);  // 100 + 100; a third would make 300
  EXPECT_EQ(first[1].job_id, 1);
  // Over the bound from the first unit: one unit all the same, none without first_free.
  bound.max_samples = 50;
  bound.first_free = false;
  EXPECT_TRUE(s.pick(7, 0, 16, bound).empty());
  bound.first_free = true;
  const std::vector<Scheduler::Pick> one = s.pick(7, 0, 16, bound);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].job_id, 1);
  // Job 1's last unit (100 samples) is over the bound: the call ends there, job 2's units of 10
  // samples (which would fit) wait their turn.
  bound.max_samples = 50;
  bound.first_free = false;
  EXPECT_TRUE(s.pick(7, 0, 16, bound).empty());
  bound.first_free = true;
  const std::vector<Scheduler::Pick> last = s.pick(7, 0, 16, bound);
  ASSERT_EQ(last.size(), 1u);  // free; then 100 + 10 > 50
  EXPECT_EQ(last[0].job_id, 1);
  // Job 2's units, 10 samples each: as many as the bound holds.
  bound.max_samples = 35;
  EXPECT_EQ(s.pick(7, 0, 16, bound).size(), 3u);
  // Without the function, only the count bounds.
  EXPECT_EQ(s.pick(7, 0, 16, Scheduler::SampleBound{}).size(), 1u);
}

TEST(SchedulerPolicy, APriorityChangeReorders) {
  Scheduler s;
  s.put_job(policy_job(1, 1, 2, 0, 0));
  s.put_job(policy_job(2, 1, 2, 0, 10));
  EXPECT_EQ(s.pick(7, 0, 1).at(0).job_id, 1);
  s.set_priority(2, 3);
  EXPECT_EQ(s.pick(7, 0, 1).at(0).job_id, 2);
}

TEST(SchedulerPolicy, WithinAJobBatchThenTileWithoutABarrier) {
  Scheduler s;
  s.put_job(policy_job(1, 2, 3));
  const std::vector<Scheduler::Pick> picks = s.pick(7, 0, 100);
  EXPECT_EQ(order_of(picks), (Order{{0, 0}, {0, 1}, {1, 0}, {1, 1}, {2, 0}, {2, 1}}));
  for (const Scheduler::Pick& p : picks) EXPECT_TRUE(p.unborn);
}

TEST(SchedulerPolicy, AUnitBackInTheQueueGoesInItsBatchOrder) {
  Scheduler s;
  s.put_job(policy_job(1, 2, 3));
  ASSERT_EQ(order_of(s.pick(7, 0, 3)), (Order{{0, 0}, {0, 1}, {1, 0}}));
  s.requeued(1, {0, 0, /*unit_id=*/41});
  const std::vector<Scheduler::Pick> rest = s.pick(7, 0, 100);
  EXPECT_EQ(order_of(rest), (Order{{0, 0}, {1, 1}, {2, 0}, {2, 1}}));
  EXPECT_FALSE(rest[0].unborn);
  EXPECT_EQ(rest[0].unit_id, 41);
}

TEST(SchedulerPolicy, TheFirstPickStartsTheJob) {
  Scheduler s;
  s.put_job(policy_job(1, 1, 2));
  EXPECT_EQ(s.started_unix_ms(1), 0);
  s.pick(7, 123, 1);
  EXPECT_EQ(s.started_unix_ms(1), 123);
  s.pick(7, 456, 1);
  EXPECT_EQ(s.started_unix_ms(1), 123);
}

TEST(SchedulerPolicy, ATimeJobPastItsBudgetGetsBatchZeroOnly) {
  Scheduler s;
  Scheduler::Job job = policy_job(1, 3, 4);
  job.time_budget_ms = 1000;
  s.put_job(job);
  ASSERT_EQ(order_of(s.pick(7, /*now=*/500, 1)), (Order{{0, 0}}));  // the budget starts here
  s.requeued(1, {0, 0, 11});
  // Within the budget: the queue's order, batch 1 included.
  ASSERT_EQ(order_of(s.pick(7, 1499, 4)), (Order{{0, 0}, {0, 1}, {0, 2}, {1, 0}}));
  s.requeued(1, {0, 2, 12});
  s.requeued(1, {1, 0, 13});
  // At the budget: what is left of batch 0 (a unit back in the queue included), nothing else.
  const std::vector<Scheduler::Pick> late = s.pick(7, 1500, 100);
  EXPECT_EQ(order_of(late), (Order{{0, 2}}));
  EXPECT_EQ(late.at(0).unit_id, 12);
  EXPECT_TRUE(s.pick(7, 5000, 100).empty());
}

TEST(SchedulerPolicy, ANoiseTileIsLeasedAtMostTheLookaheadPastItsPrefix) {
  Scheduler s;
  Scheduler::Job job = policy_job(1, 2, 10);
  job.noise = true;
  s.put_job(job);
  // Batches 0 and 1 of each tile (kNoiseLookahead = 2), then nothing until a merge.
  EXPECT_EQ(order_of(s.pick(7, 0, 100)), (Order{{0, 0}, {0, 1}, {1, 0}, {1, 1}}));
  s.tile_merged(1, 1, /*next_batch=*/1, /*closed=*/false);
  EXPECT_EQ(order_of(s.pick(7, 0, 100)), (Order{{2, 1}}));
}

TEST(SchedulerPolicy, ANoiseUnitBackInTheQueueWaitsForTheLookaheadToo) {
  Scheduler s;
  Scheduler::Job job = policy_job(1, 1, 10);
  job.noise = true;
  job.tiles[0] = Scheduler::Tile{/*next_lease=*/4, /*lease_end=*/10, /*next_batch=*/0};
  job.requeued.push_back({/*batch=*/3, /*tile=*/0, /*unit_id=*/31});
  s.put_job(job);
  EXPECT_TRUE(s.pick(7, 0, 100).empty());
  s.tile_merged(1, 0, 2, false);  // batch 3 is within the lookahead now, batch 4 not yet
  const std::vector<Scheduler::Pick> picks = s.pick(7, 0, 100);
  EXPECT_EQ(order_of(picks), (Order{{3, 0}}));
  EXPECT_EQ(picks.at(0).unit_id, 31);
  s.tile_merged(1, 0, 3, false);
  EXPECT_EQ(order_of(s.pick(7, 0, 100)), (Order{{4, 0}}));
}

TEST(SchedulerPolicy, AClosedTileIsLeasedNoMore) {
  Scheduler s;
  s.put_job(policy_job(1, 2, 3));
  ASSERT_EQ(order_of(s.pick(7, 0, 2)), (Order{{0, 0}, {0, 1}}));
  s.requeued(1, {0, 0, 5});
  s.tile_merged(1, 0, 1, /*closed=*/true);
  EXPECT_EQ(order_of(s.pick(7, 0, 100)), (Order{{1, 1}, {2, 1}}));
}

TEST(SchedulerPolicy, ABlockedWorkerGetsOtherJobsUntilForgiven) {
  Scheduler s;
  s.set_block_policy(/*failures_to_block=*/2, /*forgive_ms=*/1000);
  Scheduler::Job failing = policy_job(1, 1, 5, /*priority=*/9);
  failing.failures[7] = {2, /*last failure at*/ 100};
  failing.failures[8] = {1, 100};  // one failure does not block
  s.put_job(failing);
  s.put_job(policy_job(2, 1, 5));
  EXPECT_EQ(s.pick(7, 1099, 1).at(0).job_id, 2);
  EXPECT_EQ(s.pick(8, 1099, 1).at(0).job_id, 1);
  EXPECT_EQ(s.pick(7, 1100, 1).at(0).job_id, 1);  // forgiven
}

TEST(SchedulerPolicy, TakingAUnitAgainSucceedsOnlyWhileItIsLeasable) {
  // The book applies its unwritten grants again after a job is put again (LeaseBook::put_job).
  Scheduler s;
  s.put_job(policy_job(1, 1, 3));
  const Scheduler::Pick first = s.pick(7, 0, 1).at(0);
  s.put_job(policy_job(1, 1, 3));  // as the store has it: nothing leased yet
  EXPECT_TRUE(s.take(first, 0));
  EXPECT_FALSE(s.take(first, 0));  // taken already
  EXPECT_EQ(order_of(s.pick(7, 0, 100)), (Order{{1, 0}, {2, 0}}));
  EXPECT_FALSE(s.take(Scheduler::Pick{1, 0, 0, 99, false}, 0));  // not back in the queue
  s.drop_job(1);
  EXPECT_FALSE(s.take(first, 0));
  EXPECT_TRUE(s.pick(7, 0, 100).empty());
}

TEST(Scheduler, NoWorkIsANormalAnswer) {
  StoreFixture f;
  EXPECT_EQ(f.book.lease_next(f.make_worker()), std::nullopt);
}

TEST(Scheduler, HigherPriorityFirstThenOlderFirst) {
  StoreFixture f;
  const int64_t old_low = f.make_job(8, 8, 8, 1, 1, /*priority=*/0);
  f.clock.advance(10);
  const int64_t new_high = f.make_job(8, 8, 8, 1, 1, /*priority=*/5);
  f.clock.advance(10);
  const int64_t newer_high = f.make_job(8, 8, 8, 1, 1, /*priority=*/5);
  std::vector<int64_t> order;
  for (int i = 0; i < 3; ++i) order.push_back(f.book.lease_next(f.make_worker())->job_id);
  EXPECT_EQ(order, (std::vector<int64_t>{new_high, newer_high, old_low}));
}

TEST(Scheduler, WithinAJobBatchThenTile) {
  StoreFixture f;
  const int64_t job = f.make_job(16, 8, 8, 3, 1);  // 2 tiles x 3 batches
  std::vector<std::pair<uint32_t, uint32_t>> order;  // (batch, tile)
  for (int i = 0; i < 6; ++i) {
    const Lease l = *f.book.lease_next(f.make_worker());
    EXPECT_EQ(l.job_id, job);
    order.emplace_back(l.batch, l.tile);
  }
  EXPECT_EQ(order, (std::vector<std::pair<uint32_t, uint32_t>>{
                       {0, 0}, {0, 1}, {1, 0}, {1, 1}, {2, 0}, {2, 1}}));
  EXPECT_EQ(f.book.lease_next(f.make_worker()), std::nullopt);
}

TEST(Scheduler, AskingTwiceGivesTheSameLease) {
  StoreFixture f;
  f.make_job(16, 16, 8, 4, 1);
  const int64_t w = f.make_worker();
  const Lease first = *f.book.lease_next(w);
  f.clock.advance(1000);
  const Lease second = *f.book.lease_next(w);
  EXPECT_EQ(second.lease_id, first.lease_id);
  EXPECT_EQ(second.unit_id, first.unit_id);
  // Asking again counts as a sign of life: the expiry moves on.
  EXPECT_EQ(second.expires_unix_ms, f.clock.now_unix_ms() + StoreFixture::kLeaseMs);
  // Another worker gets another unit.
  const Lease other = *f.book.lease_next(f.make_worker("other"));
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
  const Lease first = *f.book.lease_next(early);  // (0, 0)
  f.clock.advance(StoreFixture::kLeaseMs / 2);
  std::vector<std::pair<uint32_t, uint32_t>> order;
  std::vector<int64_t> held;
  for (int i = 0; i < 2; ++i) {  // (0, 1), (1, 0)
    held.push_back(f.make_worker());
    const Lease l = *f.book.lease_next(held.back());
    order.emplace_back(l.batch, l.tile);
  }
  f.clock.advance(StoreFixture::kLeaseMs / 2 + 1);
  ASSERT_EQ(f.book.expire_due(), 1);  // first's lease only
  while (const std::optional<Lease> l = f.book.lease_next(f.make_worker())) {
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
  ASSERT_TRUE(f.book.lease_next(f.make_worker()));
  EXPECT_EQ(f.jobs.get(job)->state, JobState::running);
  EXPECT_EQ(f.jobs.get(job)->started_unix_ms, f.clock.now_unix_ms());
  EXPECT_EQ(f.jobs.get(job)->counters.units_leased, 1u);
}

TEST(Scheduler, SkipsCancelledJobs) {
  StoreFixture f;
  const int64_t first = f.make_job(8, 8, 8, 1, 1, 9);
  const int64_t second = f.make_job(8, 8, 8, 1, 1, 0);
  f.jobs.cancel(first, 0);
  EXPECT_EQ(f.book.lease_next(f.make_worker())->job_id, second);
}

TEST(Scheduler, EveryUnitLeasedExactlyOnce) {
  StoreFixture f;
  f.make_job(40, 24, 8, 5, 2);  // 5 x 3 tiles, 3 batches
  std::set<std::pair<uint32_t, uint32_t>> seen;
  for (;;) {
    const std::optional<Lease> l = f.book.lease_next(f.make_worker());
    if (!l) break;
    EXPECT_TRUE(seen.emplace(l->tile, l->batch).second);
  }
  EXPECT_EQ(seen.size(), 45u);
}

}  // namespace
}  // namespace tessera::server
