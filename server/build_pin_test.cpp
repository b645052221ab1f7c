// One renderer build per job (docs/design.md, "The determinism contract"): the scheduling
// policy pins a job to the build of the worker its first unit goes to and leases it to no other
// build (unless any_build); the store pins it in the transaction that writes the first lease and
// refuses a lease of another build, whatever order two builds' grants reach it in; the pin is
// read back from the store (a restart).
#include <gtest/gtest.h>

#include <set>

#include "scheduler.h"
#include "store/jobs_table.h"
#include "store_fixture.h"

namespace tessera::server {
namespace {

using testing::StoreFixture;

Scheduler::Job pin_test_job(int64_t id, uint32_t tiles, uint32_t batches) {
  Scheduler::Job job;
  job.id = id;
  job.tiles.assign(tiles, Scheduler::Tile{0, batches, 0});
  return job;
}

TEST(BuildPin, TheFirstPickPinsTheJobAndAnotherBuildGetsNone) {
  Scheduler s;
  s.set_worker_build(1, "build A");
  s.set_worker_build(2, "build B");
  s.put_job(pin_test_job(7, 2, 2));
  EXPECT_EQ(s.pinned_build(7), std::nullopt);
  ASSERT_EQ(s.pick(1, 100, 1).size(), 1u);
  EXPECT_EQ(s.pinned_build(7), "build A");
  EXPECT_TRUE(s.pick(2, 100, 10).empty());  // work left, none for build B
  EXPECT_EQ(s.pick(1, 100, 10).size(), 3u);
}

TEST(BuildPin, AnotherBuildLeasesTheNextJobNotThePinnedOne) {
  Scheduler s;
  s.set_worker_build(1, "build A");
  s.set_worker_build(2, "build B");
  Scheduler::Job pinned = pin_test_job(1, 1, 4);
  pinned.build = "build A";  // as the store has it (a restart)
  s.put_job(pinned);
  s.put_job(pin_test_job(2, 1, 1));
  const std::vector<Scheduler::Pick> got = s.pick(2, 100, 10);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].job_id, 2);
  EXPECT_EQ(s.pinned_build(2), "build B");
}

TEST(BuildPin, AnAnyBuildJobLeasesToEveryBuildAndIsNeverPinned) {
  Scheduler s;
  s.set_worker_build(1, "build A");
  s.set_worker_build(2, "build B");
  Scheduler::Job job = pin_test_job(3, 2, 1);
  job.any_build = true;
  s.put_job(job);
  EXPECT_EQ(s.pick(1, 100, 1).size(), 1u);
  EXPECT_EQ(s.pick(2, 100, 1).size(), 1u);
  EXPECT_EQ(s.pinned_build(3), std::nullopt);
}

TEST(BuildPin, AGrantOfAnotherBuildIsVoidWhenTheBookPutsTheJobAgain) {
  Scheduler s;
  s.put_job(pin_test_job(4, 2, 1));
  ASSERT_TRUE(s.take({4, 0, 0, 0, true}, 100, "build A"));
  EXPECT_FALSE(s.take({4, 1, 0, 0, true}, 100, "build B"));
  EXPECT_TRUE(s.take({4, 1, 0, 0, true}, 100, "build A"));
}

Lease unborn_lease(int64_t job_id, uint32_t tile, int64_t worker_id, const std::string& id) {
  Lease l;
  l.lease_id = id;
  l.job_id = job_id;
  l.tile = tile;
  l.worker_id = worker_id;
  l.expires_unix_ms = 1'000'000;
  return l;
}

// The race of two builds leasing a new job's first units at once, settled in the store: the
// grants reach the store in one transaction in either order; the first pins the job, the other
// build's is refused and its unit stays leasable.
TEST(BuildPin, TheStorePinsAtTheFirstLeaseWrittenAndRefusesAnotherBuilds) {
  for (const bool a_first : {true, false}) {
    StoreFixture f;
    const int64_t job = f.make_job(16, 8, 8, 1, 1);  // 2 tiles of one batch
    const int64_t a = f.make_worker("a"), b = f.make_worker("b");
    const LeaseBook::Grant ga{unborn_lease(job, 0, a, "la"), true, 100, "build A"};
    const LeaseBook::Grant gb{unborn_lease(job, 1, b, "lb"), true, 100, "build B"};
    const std::vector<LeaseBook::Grant> grants =
        a_first ? std::vector{ga, gb} : std::vector{gb, ga};
    GrantPins pins;
    std::vector<std::optional<int64_t>> ids;
    {
      Transaction tx(f.db);
      ids = write_grants(f.db, f.leases, grants, &pins);
      tx.commit();
    }
    const std::set<int64_t>& refused = pins.refused;
    ASSERT_EQ(ids.size(), 2u);
    EXPECT_TRUE(ids[0].has_value());
    EXPECT_FALSE(ids[1].has_value());
    EXPECT_EQ(refused, std::set<int64_t>{job});
    const std::string winner = a_first ? "build A" : "build B";
    EXPECT_EQ(f.jobs.get(job)->pinned_build, winner);
    EXPECT_EQ(pins.learned.at(job).build, winner);
    // The refused unit is leasable again, by the pinned build only.
    LeaseBook& book = f.book.book();
    book.add_worker(a, "build A");
    book.add_worker(b, "build B");
    const int64_t loser = a_first ? b : a, pinned = a_first ? a : b;
    EXPECT_FALSE(f.book.lease_next(loser).has_value());
    const std::vector<Lease> got = f.book.lease_up_to(pinned, 2);  // the one held, and the other
    ASSERT_EQ(got.size(), 2u);
    EXPECT_NE(got[0].tile, got[1].tile);
  }
}

// A pin an earlier flush committed is not read again: the known one decides.
TEST(BuildPin, AKnownPinDecidesWithoutAStatement) {
  StoreFixture f;
  const int64_t job = f.make_job(8, 8, 8, 1, 1);
  const int64_t b = f.make_worker("b");
  GrantPins pins;
  pins.known[job] = JobPin{false, "build A"};
  Transaction tx(f.db);
  const uint64_t before = f.db.counters().statements;
  const std::vector<std::optional<int64_t>> ids = write_grants(
      f.db, f.leases, {LeaseBook::Grant{unborn_lease(job, 0, b, "lb"), true, 100, "build B"}},
      &pins);
  EXPECT_EQ(ids, std::vector<std::optional<int64_t>>{std::nullopt});
  EXPECT_EQ(pins.refused, std::set<int64_t>{job});
  EXPECT_EQ(f.db.counters().statements, before);
}

TEST(BuildPin, AnAnyBuildJobIsAdmittedForEveryBuildAndNotPinned) {
  StoreFixture f;
  NewJob nj;
  nj.scene_file = "scene.json";
  nj.bundle_bytes = "bundle";
  nj.bundle_sha256 = std::string(64, 'b');
  nj.options.width = nj.options.height = nj.options.tile_size = 8;
  nj.options.spp = nj.options.batch_spp = 1;
  nj.any_build = true;
  const int64_t job = f.jobs.create(nj, f.clock.now_unix_ms());
  JobsTable table(f.db);
  EXPECT_TRUE(table.pin_build(job, "build A")->admits("build A"));
  EXPECT_TRUE(table.pin_build(job, "build B")->admits("build B"));
  EXPECT_TRUE(f.jobs.get(job)->any_build);
  EXPECT_EQ(f.jobs.get(job)->pinned_build, std::nullopt);
}

// A server restart: the book is loaded from the store, pin included.
TEST(BuildPin, ThePinIsReadBackFromTheStore) {
  StoreFixture f;
  const int64_t job = f.make_job(16, 8, 8, 2, 1);
  const int64_t a = f.make_worker("a"), b = f.make_worker("b");
  f.book.book().add_worker(a, "build A");
  ASSERT_TRUE(f.book.lease_next(a).has_value());
  EXPECT_EQ(f.jobs.get(job)->pinned_build, "build A");
  testing::BookLeaser restarted(f.db, f.jobs, f.leases, f.clock);
  restarted.book().add_worker(a, "build A");
  restarted.book().add_worker(b, "build B");
  EXPECT_FALSE(restarted.lease_next(b).has_value());
  EXPECT_TRUE(restarted.lease_next(a).has_value());
}

// Migration 11: a job with accepted results of one build is pinned to it, of several any_build.
TEST(BuildPin, MigrationPinsJobsToTheBuildOfTheirResults) {
  Database db(":memory:");
  ASSERT_EQ(migrate(db, 0, 10), 10);
  JobStore jobs(db);
  NewJob nj;
  nj.scene_file = "scene.json";
  nj.bundle_bytes = "bundle";
  nj.bundle_sha256 = std::string(64, 'c');
  nj.options.width = nj.options.height = nj.options.tile_size = 8;
  nj.options.spp = nj.options.batch_spp = 1;
  const int64_t one = jobs.create(nj, 0), several = jobs.create(nj, 0), none = jobs.create(nj, 0);
  const auto contributed = [&](int64_t job, const std::string& version) {
    db.prepare("INSERT INTO job_contributors VALUES (?, 'avx2', ?)")
        ->bind(1, job)
        .bind(2, version)
        .run();
  };
  contributed(one, "build A");
  contributed(several, "build A");
  contributed(several, "build B");
  migrate(db, 0);
  EXPECT_EQ(jobs.get(one)->pinned_build, "build A");
  EXPECT_FALSE(jobs.get(one)->any_build);
  EXPECT_TRUE(jobs.get(several)->any_build);
  EXPECT_EQ(jobs.get(none)->pinned_build, std::nullopt);
  EXPECT_FALSE(jobs.get(none)->any_build);
}

}  // namespace
}  // namespace tessera::server
