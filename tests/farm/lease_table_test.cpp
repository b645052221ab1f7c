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
  const std::optional<Lease> lease = f.scheduler.lease_next(w);
  ASSERT_TRUE(lease);
  EXPECT_EQ(lease->lease_id, "lease-1");
  EXPECT_EQ(lease->worker_id, w);
  EXPECT_EQ(lease->expires_unix_ms, f.clock.now_unix_ms() + StoreFixture::kLeaseMs);
  const std::optional<Lease> held = f.leases.held_by(w);
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
  const Lease lease = *f.scheduler.lease_next(w);
  f.clock.advance(StoreFixture::kLeaseMs);  // expiry is "before now": not yet at now == expiry
  EXPECT_EQ(f.leases.expire_due(), 0);
  f.clock.advance(1);
  EXPECT_EQ(f.leases.expire_due(), 1);
  EXPECT_EQ(f.leases.held_by(w), std::nullopt);
  EXPECT_EQ(f.leases.heartbeat(w, lease.lease_id), std::nullopt);
  EXPECT_EQ(f.jobs.get(job)->counters.leases_expired, 1u);
  EXPECT_EQ(f.workers.get(w)->units_lost, 1u);
  // The unit is back in the queue: the next lease is the same unit with a new id.
  const Lease again = *f.scheduler.lease_next(w);
  EXPECT_EQ(again.unit_id, lease.unit_id);
  EXPECT_NE(again.lease_id, lease.lease_id);
}

TEST(LeaseTable, HeartbeatsExtend) {
  StoreFixture f;
  f.make_job(8, 8, 8, 2, 1);
  const int64_t w = f.make_worker();
  const Lease lease = *f.scheduler.lease_next(w);
  for (int i = 0; i < 5; ++i) {
    f.clock.advance(StoreFixture::kLeaseMs / 2);
    const std::optional<int64_t> expires = f.leases.heartbeat(w, lease.lease_id);
    ASSERT_TRUE(expires);
    EXPECT_EQ(*expires, f.clock.now_unix_ms() + StoreFixture::kLeaseMs);
    EXPECT_EQ(f.leases.expire_due(), 0);
  }
  // Only its holder can extend it.
  const int64_t other = f.make_worker("other");
  EXPECT_EQ(f.leases.heartbeat(other, lease.lease_id), std::nullopt);
  EXPECT_EQ(f.leases.heartbeat(w, "lease-unknown"), std::nullopt);
}

TEST(LeaseTable, ReleaseReturnsTheUnitOnce) {
  StoreFixture f;
  const int64_t job = f.make_job(8, 8, 8, 2, 1);
  const int64_t w = f.make_worker();
  const Lease lease = *f.scheduler.lease_next(w);
  EXPECT_TRUE(f.leases.release(w, lease.lease_id, ReleaseReason::shutdown, "").released);
  EXPECT_FALSE(f.leases.release(w, lease.lease_id, ReleaseReason::shutdown, "").released);
  EXPECT_EQ(f.jobs.get(job)->counters.units_released, 1u);
  EXPECT_EQ(f.scheduler.lease_next(w)->unit_id, lease.unit_id);
}

TEST(LeaseTable, RepeatedFailuresBlockTheWorkerThenFailTheJob) {
  StoreFixture f;
  const int64_t job = f.make_job(8, 8, 8, 1, 1);  // a single unit
  const int64_t a = f.make_worker("a"), b = f.make_worker("b");
  for (int i = 0; i < LeaseTable::kWorkerFailuresToBlock; ++i) {
    const Lease lease = *f.scheduler.lease_next(a);
    EXPECT_FALSE(f.leases.release(a, lease.lease_id, ReleaseReason::failed, "no memory").job_failed);
  }
  // a is blocked from the job; b still gets its unit.
  EXPECT_EQ(f.scheduler.lease_next(a), std::nullopt);
  const Lease lease = *f.scheduler.lease_next(b);
  const ReleaseOutcome third = f.leases.release(b, lease.lease_id, ReleaseReason::failed, "bad mesh");
  EXPECT_TRUE(third.job_failed);
  const JobRecord failed = *f.jobs.get(job);
  EXPECT_EQ(failed.state, JobState::failed);
  EXPECT_NE(failed.error.find("bad mesh"), std::string::npos) << failed.error;
  EXPECT_EQ(f.scheduler.lease_next(b), std::nullopt);
}

TEST(LeaseTable, RevokeAllRequeuesEveryLease) {
  StoreFixture f;
  const int64_t job = f.make_job(16, 16, 8, 1, 1);
  const int64_t a = f.make_worker("a"), b = f.make_worker("b");
  const Lease la = *f.scheduler.lease_next(a);
  const Lease lb = *f.scheduler.lease_next(b);
  EXPECT_EQ(f.leases.revoke_all(), 2);
  EXPECT_EQ(f.jobs.get(job)->counters.units_leased, 0u);
  EXPECT_EQ(f.jobs.get(job)->counters.leases_expired, 2u);
  EXPECT_EQ(f.leases.heartbeat(a, la.lease_id), std::nullopt);
  EXPECT_EQ(f.leases.heartbeat(b, lb.lease_id), std::nullopt);
}

}  // namespace
}  // namespace tessera::server
