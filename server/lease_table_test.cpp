// Leases on a fake clock: expiry, heartbeats, hand-backs, failures.
#include <gtest/gtest.h>

#include "store_fixture.h"

namespace tessera::server {
namespace {

using testing::StoreFixture;

TEST(LeaseTable, GrantSetsIdAndExpiry) {
  StoreFixture f;
  f.make_job(8, 8, 8, 2, 1);
  const int64_t w = f.make_worker();
  const std::optional<Lease> lease = f.book.lease_next(w);
  ASSERT_TRUE(lease);
  EXPECT_EQ(lease->lease_id, "lease-1");
  EXPECT_EQ(lease->worker_id, w);
  EXPECT_EQ(lease->expires_unix_ms, f.clock.now_unix_ms() + StoreFixture::kLeaseMs);
  // Written to the store with the book's id (FarmStore::flush_leases).
  const std::optional<Lease> held = UnitsTable(f.db).lease(w, lease->lease_id);
  ASSERT_TRUE(held);
  EXPECT_EQ(held->lease_id, lease->lease_id);
  EXPECT_EQ(held->unit_id, lease->unit_id);
}

TEST(LeaseTable, RandomLeaseIdsAre128BitHex) {
  const std::string a = random_lease_id(), b = random_lease_id();
  EXPECT_EQ(a.size(), 32u);
  EXPECT_EQ(a.find_first_not_of("0123456789abcdef"), std::string::npos);
  EXPECT_NE(a, b);
}

TEST(LeaseTable, ExpiresOnlyAfterItsTime) {
  StoreFixture f;
  const int64_t job = f.make_job(8, 8, 8, 2, 1);
  const int64_t w = f.make_worker();
  const Lease lease = *f.book.lease_next(w);
  f.clock.advance(StoreFixture::kLeaseMs);  // expiry is "before now": not yet at now == expiry
  EXPECT_EQ(f.book.expire_due(), 0);
  f.clock.advance(1);
  EXPECT_EQ(f.book.expire_due(), 1);
  EXPECT_EQ(UnitsTable(f.db).lease(w, lease.lease_id), std::nullopt);
  EXPECT_EQ(f.book.heartbeat(w, lease.lease_id), std::nullopt);
  EXPECT_EQ(f.jobs.get(job)->counters.leases_expired, 1u);
  EXPECT_EQ(f.workers.get(w)->units_lost, 1u);
  // The unit is back in the queue: the next lease is the same unit with a new id.
  const Lease again = *f.book.lease_next(w);
  EXPECT_EQ(again.unit_id, lease.unit_id);
  EXPECT_NE(again.lease_id, lease.lease_id);
}

TEST(LeaseTable, HeartbeatsExtend) {
  StoreFixture f;
  f.make_job(8, 8, 8, 2, 1);
  const int64_t w = f.make_worker();
  const Lease lease = *f.book.lease_next(w);
  for (int i = 0; i < 5; ++i) {
    f.clock.advance(StoreFixture::kLeaseMs / 2);
    const std::optional<int64_t> expires = f.book.heartbeat(w, lease.lease_id);
    ASSERT_TRUE(expires);
    EXPECT_EQ(*expires, f.clock.now_unix_ms() + StoreFixture::kLeaseMs);
    EXPECT_EQ(f.book.expire_due(), 0);
  }
  // Only its holder can extend it.
  const int64_t other = f.make_worker("other");
  EXPECT_EQ(f.book.heartbeat(other, lease.lease_id), std::nullopt);
  EXPECT_EQ(f.book.heartbeat(w, "lease-unknown"), std::nullopt);
}

TEST(LeaseTable, ReleaseReturnsTheUnitOnce) {
  StoreFixture f;
  const int64_t job = f.make_job(8, 8, 8, 2, 1);
  const int64_t w = f.make_worker();
  const Lease lease = *f.book.lease_next(w);
  EXPECT_TRUE(f.leases.release(w, lease.lease_id, ReleaseReason::shutdown, "").released);
  EXPECT_FALSE(f.leases.release(w, lease.lease_id, ReleaseReason::shutdown, "").released);
  EXPECT_EQ(f.jobs.get(job)->counters.units_released, 1u);
  EXPECT_EQ(f.book.lease_next(w)->unit_id, lease.unit_id);
}

/// Leases the next unit for `worker` and hands it back as failed with `why`.
ReleaseOutcome fail_next(testing::StoreFixture& f, int64_t worker, const std::string& why) {
  const std::optional<Lease> lease = f.book.lease_next(worker);
  EXPECT_TRUE(lease) << "worker " << worker << " got no unit";
  if (!lease) return {};
  return f.leases.release(worker, lease->lease_id, ReleaseReason::failed, why);
}

TEST(WorkerHealth, FailuresBlockAWorkerFromTheJobUntilForgiven) {
  StoreFixture f;
  WorkerHealthPolicy policy;
  policy.failures_to_block = 2;
  policy.forgive_ms = 60'000;
  policy.workers_to_fail_unit = 3;
  f.leases.set_health_policy(policy);
  const int64_t job = f.make_job(16, 8, 8, 1, 1);  // two units
  const int64_t other_job = f.make_job(8, 8, 8, 1, 1);
  const int64_t a = f.make_worker("a");
  EXPECT_FALSE(fail_next(f, a, "out of memory").job_failed);
  EXPECT_FALSE(fail_next(f, a, "out of memory").job_failed);
  // Blocked from `job` (both its units are queued again), not from other jobs.
  const Lease elsewhere = *f.book.lease_next(a);
  EXPECT_EQ(elsewhere.job_id, other_job);
  f.leases.release(a, elsewhere.lease_id, ReleaseReason::shutdown, "");
  f.jobs.cancel(other_job, f.clock.now_unix_ms());
  EXPECT_EQ(f.book.lease_next(a), std::nullopt);
  f.clock.advance(policy.forgive_ms - 1);
  EXPECT_EQ(f.book.lease_next(a), std::nullopt);  // still inside the window
  f.clock.advance(1);
  // Forgiven: it gets the job's units again, and its count starts over (one failure does not
  // block it again at once).
  EXPECT_FALSE(fail_next(f, a, "out of memory").job_failed);
  const std::optional<Lease> again = f.book.lease_next(a);
  ASSERT_TRUE(again);
  EXPECT_EQ(again->job_id, job);
  EXPECT_EQ(f.jobs.get(job)->state, JobState::running);
}

TEST(WorkerHealth, AUnitFailingOnKWorkersFailsTheJobWithEveryReason) {
  StoreFixture f;
  WorkerHealthPolicy policy;
  policy.failures_to_block = 2;
  policy.workers_to_fail_unit = 3;
  f.leases.set_health_policy(policy);
  const int64_t job = f.make_job(8, 8, 8, 1, 1);  // a single unit
  const int64_t a = f.make_worker("alpha"), b = f.make_worker("beta"), c = f.make_worker("gamma");
  EXPECT_FALSE(fail_next(f, a, "bad mesh on alpha").job_failed);
  EXPECT_FALSE(fail_next(f, a, "bad mesh on alpha").job_failed);  // alpha is now blocked
  EXPECT_EQ(f.book.lease_next(a), std::nullopt);
  EXPECT_FALSE(fail_next(f, b, "segfault on beta").job_failed);  // 2 workers: not yet
  EXPECT_EQ(f.jobs.get(job)->state, JobState::running);
  EXPECT_TRUE(fail_next(f, c, "NaN flood on gamma").job_failed);  // the third worker
  const JobRecord failed = *f.jobs.get(job);
  EXPECT_EQ(failed.state, JobState::failed);
  for (const char* part : {"tile 0, batch 0", "on 3 worker(s)", "alpha): bad mesh on alpha",
                           "beta): segfault on beta", "gamma): NaN flood on gamma"}) {
    EXPECT_NE(failed.error.find(part), std::string::npos) << part << " in: " << failed.error;
  }
  EXPECT_EQ(f.book.lease_next(b), std::nullopt);
}

TEST(WorkerHealth, AFarmWithFewerWorkersStillEndsAJobThatAlwaysFails) {
  StoreFixture f;
  WorkerHealthPolicy policy;
  policy.failures_to_block = 2;
  policy.forgive_ms = 1000;
  policy.workers_to_fail_unit = 3;
  f.leases.set_health_policy(policy);
  const int64_t job = f.make_job(8, 8, 8, 1, 1);
  const int64_t only = f.make_worker("only");
  // 3 workers x 2 failures = 6 attempts in all fail the job, even on one worker.
  for (int attempt = 1; attempt <= 6; ++attempt) {
    const ReleaseOutcome outcome = fail_next(f, only, "renderer error");
    EXPECT_EQ(outcome.job_failed, attempt == 6) << attempt;
    if (attempt % 2 == 0) f.clock.advance(policy.forgive_ms + 1);  // wait out the block
  }
  EXPECT_EQ(f.jobs.get(job)->state, JobState::failed);
}

TEST(WorkerHealth, ShutdownReleasesCountNothing) {
  StoreFixture f;
  const int64_t job = f.make_job(8, 8, 8, 1, 1);
  const int64_t a = f.make_worker("a");
  for (int i = 0; i < 10; ++i) {
    const Lease lease = *f.book.lease_next(a);
    EXPECT_FALSE(f.leases.release(a, lease.lease_id, ReleaseReason::shutdown, "").job_failed);
  }
  EXPECT_EQ(f.jobs.get(job)->state, JobState::running);
  EXPECT_TRUE(f.book.lease_next(a));
}

TEST(LeaseTable, RevokeAllRequeuesEveryLease) {
  StoreFixture f;
  const int64_t job = f.make_job(16, 16, 8, 1, 1);
  const int64_t a = f.make_worker("a"), b = f.make_worker("b");
  const Lease la = *f.book.lease_next(a);
  const Lease lb = *f.book.lease_next(b);
  EXPECT_EQ(f.leases.revoke_all(), 2);
  EXPECT_EQ(f.jobs.get(job)->counters.units_leased, 0u);
  EXPECT_EQ(f.jobs.get(job)->counters.leases_expired, 2u);
  EXPECT_EQ(f.book.heartbeat(a, la.lease_id), std::nullopt);
  EXPECT_EQ(f.book.heartbeat(b, lb.lease_id), std::nullopt);
}

}  // namespace
}  // namespace tessera::server
