// Deleting jobs (JobStore::remove): only final jobs, everything of the job goes, its bundle when
// no other job uses it, and the freed pages go back to the file (incremental auto-vacuum,
// migration 5).
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "coordinator.h"
#include "farm_error.h"
#include "store_fixture.h"

namespace tessera::server {
namespace {

using testing::StoreFixture;
using testing::result_for;

int64_t pragma(Database& db, const std::string& name) {
  auto q = db.prepare("PRAGMA " + name);
  EXPECT_TRUE(q->step());
  return q->int64(0);
}

int64_t count(Database& db, const std::string& table) {
  auto q = db.prepare("SELECT COUNT(*) FROM " + table);
  EXPECT_TRUE(q->step());
  return q->int64(0);
}

TEST(DeleteJob, OnlyFinalJobsAndEverythingOfThemGoes) {
  StoreFixture f;
  const int64_t job = f.make_job(8, 8, 4, 4, 2);  // 4 tiles x 2 batches
  EXPECT_EQ(f.jobs.remove(job), DeleteOutcome::not_final);  // queued
  const Lease l = *f.book.lease_next(f.make_worker());
  const Accumulation acc = StoreFixture::synthetic({0, 0, 4, 4}, 0, 2);
  ASSERT_TRUE(f.merger.accept(result_for(l, acc), acc).accepted);
  EXPECT_EQ(f.jobs.remove(job), DeleteOutcome::not_final);  // running
  ASSERT_EQ(f.jobs.cancel(job, f.clock.now_unix_ms()), CancelOutcome::cancelled);
  EXPECT_EQ(f.jobs.remove(job), DeleteOutcome::deleted);
  EXPECT_FALSE(f.jobs.get(job).has_value());
  for (const char* table : {"jobs", "tiles", "tile_checkpoints", "units", "results",
                            "job_contributors", "bundles"}) {
    EXPECT_EQ(count(f.db, table), 0) << table;
  }
  EXPECT_EQ(f.jobs.remove(job), DeleteOutcome::not_found);
  EXPECT_EQ(f.jobs.remove(12345), DeleteOutcome::not_found);
}

TEST(DeleteJob, ASharedBundleStaysWithTheJobThatUsesIt) {
  StoreFixture f;
  NewJob a;
  a.scene_file = "s.json";
  a.bundle_bytes = "shared";
  a.bundle_sha256 = std::string(64, 'e');
  a.options.width = a.options.height = 4;
  a.options.tile_size = 4;
  a.options.spp = a.options.batch_spp = 1;
  const int64_t first = f.jobs.create(a, 0);
  const int64_t second = f.jobs.create(a, 0);
  f.jobs.cancel(first, 0);
  EXPECT_EQ(f.jobs.remove(first), DeleteOutcome::deleted);
  EXPECT_EQ(f.jobs.bundle_bytes(a.bundle_sha256), "shared");
  f.jobs.cancel(second, 0);
  EXPECT_EQ(f.jobs.remove(second), DeleteOutcome::deleted);
  EXPECT_FALSE(f.jobs.bundle_bytes(a.bundle_sha256).has_value());
}

TEST(DeleteJob, ReturnsItsSpace) {
  StoreFixture f;
  EXPECT_EQ(pragma(f.db, "auto_vacuum"), 2);  // incremental (migration 5)
  const int64_t before = pragma(f.db, "page_count");
  // Units and merged tiles take the space (a submit writes rows per tile only): 512 tiles of
  // 16x16, each leased and merged once, then one unit of batch 1 each leased (a row).
  const int64_t job = f.make_job(512, 256, 16, 2, 1);
  const int64_t worker = f.make_worker();
  const std::vector<TileRecord> tiles = f.tiles(job);
  for (int i = 0; i < 512; ++i) {
    const Lease l = *f.book.lease_next(worker);
    const Accumulation acc = StoreFixture::synthetic(tiles[l.tile].rect, l.batch, 1);
    ASSERT_TRUE(f.merger.accept(result_for(l, acc), acc).accepted);
  }
  const int64_t full = pragma(f.db, "page_count");
  ASSERT_GT(full - before, 500);
  f.jobs.cancel(job, 0);
  ASSERT_EQ(f.jobs.remove(job), DeleteOutcome::deleted);
  EXPECT_EQ(pragma(f.db, "freelist_count"), 0);
  EXPECT_LT(pragma(f.db, "page_count") - before, (full - before) / 20);
}

TEST(DeleteJob, FinishedBeforeListsOnlyOldFinalJobs) {
  StoreFixture f;
  const int64_t old_job = f.make_job(4, 4, 4, 1, 1);
  const int64_t running = f.make_job(4, 4, 4, 1, 1);
  f.jobs.cancel(old_job, 1'000);
  f.book.lease_next(f.make_worker());  // the cancelled job is passed over: starts `running`
  EXPECT_EQ(f.jobs.get(running)->state, JobState::running);
  EXPECT_EQ(f.jobs.finished_before(2'000), std::vector<int64_t>{old_job});
  EXPECT_TRUE(f.jobs.finished_before(1'000).empty());
}

// --retention-days through the coordinator: a final job older than the retention is deleted by
// the reaper's periodic call, a younger one and an unfinished one are kept.
TEST(DeleteJob, RetentionDeletesOnlyOldFinalJobs) {
  testing::FakeClock clock;
  CoordinatorConfig config;
  config.db_path = ":memory:";
  config.output_dir = std::filesystem::temp_directory_path() / "tessera-retention-test";
  config.retention_days = 1;
  Coordinator coordinator(config, clock);
  const v1::SceneBundle bundle = testing::tiny_bundle();
  const int64_t old_job = coordinator.submit(bundle, {}, 0, "c").id;
  coordinator.cancel(old_job);
  clock.advance(3'600'000);
  const int64_t young_job = coordinator.submit(bundle, {}, 0, "c").id;
  coordinator.cancel(young_job);
  const int64_t queued_job = coordinator.submit(bundle, {}, 0, "c").id;
  clock.advance(86'400'000 - 3'600'000 - 30'000);  // the old job ended a day less 30 s ago
  EXPECT_EQ(coordinator.apply_retention(), 0);     // nothing a day old yet
  clock.advance(31'000);                           // now it is, but the last check was 31 s ago
  EXPECT_EQ(coordinator.apply_retention(), 0);     // at most once a minute
  clock.advance(30'000);
  EXPECT_EQ(coordinator.apply_retention(), 1);
  EXPECT_THROW(coordinator.job(old_job), FarmError);
  EXPECT_EQ(coordinator.job(young_job).state, JobState::cancelled);
  EXPECT_EQ(coordinator.job(queued_job).state, JobState::queued);
  // Deleting by hand: an unknown or unfinished job is refused, naming why.
  try {
    coordinator.remove(queued_job);
    ADD_FAILURE() << "a queued job was deleted";
  } catch (const FarmError& e) {
    EXPECT_EQ(std::string(e.what()),
              "job " + std::to_string(queued_job) + " is queued: cancel it first");
    EXPECT_EQ(e.code(), ErrorCode::failed_precondition);
  }
  EXPECT_THROW(coordinator.remove(old_job), FarmError);
}

}  // namespace
}  // namespace tessera::server
