// The progressive batch schedule in the store: breadth-first leasing sharpens the whole image
// round by round, and databases from before schedules keep their fixed batches.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "store_fixture.h"

namespace tessera::server {
namespace {

using testing::StoreFixture;
using testing::result_for;

/// A default job: 192x192 in 64-px tiles, 256 spp, progressive up to a 256-spp cap.
int64_t make_default_job(StoreFixture& f) {
  NewJob job;
  job.scene_file = "scene.json";
  job.bundle_bytes = "progressive bundle";
  job.bundle_sha256 = std::string(64, 'd');
  job.options.width = job.options.height = 192;
  job.options.tile_size = 64;
  job.options.spp = 256;
  const JobPlan plan = make_job_plan(192, 192, 64, 256, 0);
  job.options.batch_spp = plan.batch_spp;
  job.options.batch_kind = plan.batch_kind;
  return f.jobs.create(job, f.clock.now_unix_ms());
}

std::vector<uint32_t> tile_spp(StoreFixture& f, int64_t job) {
  std::vector<uint32_t> out;
  for (const TileRecord& t : f.tiles(job)) out.push_back(t.spp);
  return out;
}

// A scripted worker uploads one unit at a time; after each round of the schedule (one unit per
// tile), every tile's merged spp grew, to the schedule's end of that round.
TEST(Progressive, EveryRoundSharpensEveryTile) {
  StoreFixture f;
  const int64_t job = make_default_job(f);
  const JobRecord record = *f.jobs.get(job);
  ASSERT_EQ(record.options.batch_kind, BatchKind::progressive);
  const BatchSchedule schedule = record.options.plan().schedule();
  ASSERT_EQ(record.tile_count, 9u);
  ASSERT_EQ(record.batch_count, 9u);  // 1, 1, 2, 4, ..., 128
  const int64_t w = f.make_worker();
  std::vector<uint32_t> before = tile_spp(f, job);
  for (uint32_t round = 0; round < record.batch_count; ++round) {
    for (uint32_t i = 0; i < record.tile_count; ++i) {
      const Lease l = *f.book.lease_next(w);
      ASSERT_EQ(l.batch, round) << "breadth first: round " << round << " unit " << i;
      const uint32_t samples = schedule.end(l.batch) - schedule.begin(l.batch);
      const TileRect rect = *f.jobs.tile_rect(job, l.tile);
      const Accumulation acc = StoreFixture::synthetic(rect, l.batch, samples);
      ASSERT_TRUE(f.merger.accept(result_for(l, acc), acc).accepted);
    }
    const std::vector<uint32_t> after = tile_spp(f, job);
    for (size_t t = 0; t < after.size(); ++t) {
      EXPECT_GT(after[t], before[t]) << "tile " << t << " round " << round;
      EXPECT_EQ(after[t], schedule.end(round)) << "tile " << t << " round " << round;
    }
    const JobRecord r = *f.jobs.get(job);
    EXPECT_EQ(r.spp_merged, schedule.end(round));
    before = after;
  }
  EXPECT_EQ(before, std::vector<uint32_t>(9, 256u));
  EXPECT_TRUE(f.jobs.get(job)->complete);
  EXPECT_EQ(f.jobs.get(job)->progress(), 1.0);
}

// Breadth first without a barrier: batch 1 is leased while batch 0 results are still out.
TEST(Progressive, NextBatchLeasedWithoutWaitingForResults) {
  StoreFixture f;
  const int64_t job = make_default_job(f);
  std::vector<Lease> held;
  for (int i = 0; i < 10; ++i) held.push_back(*f.book.lease_next(f.make_worker()));
  for (int i = 0; i < 9; ++i) EXPECT_EQ(held[size_t(i)].batch, 0u);
  EXPECT_EQ(held[9].batch, 1u);
  EXPECT_EQ(held[9].tile, 0u);
  EXPECT_EQ(f.jobs.get(job)->counters.units_done, 0u);
}

// A job stored before schedules (migration 4) keeps its fixed batches.
TEST(Migration4, JobsStoredBeforeKeepFixedBatches) {
  Database db(":memory:");
  schema_version(db);
  for (const Migration& m : schema_migrations()) {
    if (m.version >= 4) break;
    db.exec(m.sql);
    db.exec("INSERT INTO schema_migrations VALUES (" + std::to_string(m.version) + ", 'v', 0)");
  }
  db.exec("INSERT INTO bundles VALUES ('" + std::string(64, 'c') + "', 's.json', x'00', 1, 0);"
          "INSERT INTO jobs (state, priority, bundle_sha256, scene_file, width, height, spp,"
          " max_depth, seed, tile_size, batch_spp, isa, tile_count, batch_count, units_total,"
          " submitted_unix_ms) VALUES ('running', 0, '" + std::string(64, 'c') +
          "', 's.json', 16, 8, 64, -1, 0, 8, 16, '', 2, 4, 8, 0);"
          "INSERT INTO tiles (job_id, tile, x0, y0, x1, y1, next_batch) VALUES"
          " (1, 0, 0, 0, 8, 8, 3), (1, 1, 8, 0, 16, 8, 1);");
  migrate(db, 5);
  JobStore jobs(db);
  const JobRecord r = *jobs.get(1);
  EXPECT_EQ(r.options.batch_kind, BatchKind::fixed);
  EXPECT_EQ(r.options.plan().batch_count(), 4u);
  EXPECT_EQ(r.options.plan().batch_begin(2), 32u);
  EXPECT_EQ(r.spp_merged, 16u);
  EXPECT_EQ(r.reached.spp_max, 48u);
  EXPECT_EQ(jobs.tiles(1).at(0).spp, 48u);
  EXPECT_EQ(jobs.spec(1)->options.batch_kind, BatchKind::fixed);
}

}  // namespace
}  // namespace tessera::server
