// The results table (server/store/results_table.h, migration 8): one row per accepted result
// not yet in its tile's checkpoint, written once; merged or waiting by the tile's next_batch.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "accum/accumulation_codec.h"
#include "store/results_table.h"
#include "store_fixture.h"

namespace tessera::server {
namespace {

using testing::StoreFixture;
using testing::result_for;

/// A job of 4-px tiles, `width` x 4 px, 4 spp in batches of 1, for the migration tests.
int64_t create_migrated_job(JobStore& jobs, char sha_digit, uint32_t width) {
  NewJob nj;
  nj.bundle_sha256 = std::string(64, sha_digit);
  nj.scene_file = "s.json";
  nj.bundle_bytes = "b";
  nj.options.width = width;
  nj.options.height = nj.options.tile_size = 4;
  nj.options.spp = 4;
  nj.options.batch_spp = 1;
  return jobs.create(nj, 0);
}

int64_t count_rows(Database& db, const std::string& sql) {
  auto q = db.prepare(sql);
  EXPECT_TRUE(q->step());
  return q->int64(0);
}

void set_next_batch(Database& db, int64_t job, uint32_t tile, uint32_t next) {
  db.prepare("UPDATE tiles SET next_batch = ? WHERE job_id = ? AND tile = ?")
      ->bind(1, next)
      .bind(2, job)
      .bind(3, tile)
      .run();
}

TEST(ResultsTable, MergedOrWaitingByTheTilesNextBatch) {
  StoreFixture f;
  const int64_t job = f.make_job(8, 4, 4, 8, 1);  // 2 tiles x 8 batches
  ResultsTable results(f.db);
  for (uint32_t b : {1u, 2u, 5u, 6u}) results.append(job, 0, b, "t0b" + std::to_string(b));
  results.append(job, 1, 3, "t1b3");
  set_next_batch(f.db, job, 0, 3);  // tile 0: checkpoint [0, 1), merged 1 and 2, 5 and 6 wait
  EXPECT_EQ(results.first_merged(job, 0, 3), 1u);
  EXPECT_EQ(results.first_merged(job, 1, 0), 0u);  // none merged: next_batch itself
  std::vector<uint32_t> merged;
  results.for_each_merged(job, 0, 3, [&](uint32_t b, const std::string& bytes) {
    EXPECT_EQ(bytes, "t0b" + std::to_string(b));
    merged.push_back(b);
  });
  EXPECT_EQ(merged, (std::vector<uint32_t>{1, 2}));
  EXPECT_EQ(results.find(job, 0, 5), "t0b5");
  EXPECT_EQ(results.find(job, 0, 4), std::nullopt);
  EXPECT_EQ(results.tiles_with_merged(job), std::vector<uint32_t>{0});

  // The job ends: waiting rows go (tile 0's 5 and 6, tile 1's 3), merged ones stay.
  EXPECT_EQ(results.drop_waiting_of_job(job), 3);
  EXPECT_EQ(results.count(job), 2);
  EXPECT_EQ(results.drop_merged(job, 0, 3), 2);
  EXPECT_EQ(results.count(job), 0);
  EXPECT_TRUE(results.tiles_with_merged(job).empty());

  // A second row for the same batch is refused by the primary key.
  results.append(job, 1, 4, "once");
  EXPECT_THROW(results.append(job, 1, 4, "twice"), SqliteError);
  EXPECT_EQ(results.drop_waiting_of_tile(job, 1, 4), 1);
}

// Each accepted result is inserted at most once and never updated or copied, whatever order
// the results of a tile arrive in (before migration 8 one that arrived early was written to
// pending_results, then again to merged_results); the tiles' sums are the in-order ones.
TEST(ResultsTable, AnAcceptedResultIsWrittenOnce) {
  StoreFixture f;
  f.db.exec(
      "CREATE TEMP TABLE writes (inserts INTEGER, updates INTEGER);"
      "INSERT INTO writes VALUES (0, 0);"
      "CREATE TEMP TRIGGER count_inserts AFTER INSERT ON main.results"
      " BEGIN UPDATE writes SET inserts = inserts + 1; END;"
      "CREATE TEMP TRIGGER count_updates AFTER UPDATE ON main.results"
      " BEGIN UPDATE writes SET updates = updates + 1; END;");
  const int64_t job = f.make_job(8, 8, 4, 24, 1);  // 4 tiles x 24 batches
  const std::vector<TileRecord> rects = f.jobs.tiles(job);
  TileMerger merger(f.db, f.clock, MergeCache::kDefaultBudgetBytes, 1000);  // no checkpoints
  std::mt19937 rng(11);
  int accepted = 0, early = 0;
  for (;;) {
    std::vector<Lease> round;
    for (int i = 0; i < 12; ++i) {
      if (const auto l = f.book.lease_next(f.make_worker())) round.push_back(*l);
    }
    if (round.empty()) break;
    std::shuffle(round.begin(), round.end(), rng);
    for (const Lease& l : round) {
      const Accumulation acc = StoreFixture::synthetic(rects[l.tile].rect, l.batch, 1);
      const AcceptOutcome o = merger.accept(result_for(l, acc), acc);
      ASSERT_TRUE(o.accepted);
      ++accepted;
      early += o.merged == 0;
    }
  }
  EXPECT_GT(early, accepted / 4);  // the shuffle made many arrive before their predecessor
  // Every tile finished at 24 spp: checkpointed, so no row is left...
  EXPECT_EQ(ResultsTable(f.db).count(job), 0);
  // ...and each result went in once, except the one whose merge finished its tile (4 tiles):
  // that merge checkpoints the tile, so its bytes are not written at all.
  EXPECT_EQ(count_rows(f.db, "SELECT inserts FROM writes"), accepted - 4);
  EXPECT_EQ(count_rows(f.db, "SELECT updates FROM writes"), 0);
  for (const TileRecord& t : f.tiles(job)) {
    Accumulation expected(t.rect);
    for (uint32_t b = 0; b < 24; ++b) expected.merge(StoreFixture::synthetic(t.rect, b, 1));
    EXPECT_EQ(decode_accumulation(t.accumulation), expected) << "tile " << t.tile;
  }
}

// Migration 8 moves merged_results and pending_results into `results` unchanged: the merged
// rows still continue the checkpoint, the waiting ones still wait.
TEST(ResultsTable, MigrationMovesMergedAndPendingRows) {
  testing::FakeClock clock;
  Database db(":memory:");
  ASSERT_EQ(migrate(db, 0, 7), 7);
  JobStore jobs(db);
  const int64_t job = create_migrated_job(jobs, 'm', 4);
  const TileRect rect{0, 0, 4, 4};
  std::vector<Accumulation> batch;
  for (uint32_t b = 0; b < 4; ++b) batch.push_back(StoreFixture::synthetic(rect, b, 1));
  // As a schema-7 server left it: batch 0 checkpointed, 1 merged since, 3 waiting for 2.
  db.prepare("UPDATE tiles SET accumulation = ?, next_batch = 2 WHERE job_id = ? AND tile = 0")
      ->bind_blob(1, encode_accumulation(batch[0]))
      .bind(2, job)
      .run();
  db.prepare("INSERT INTO merged_results VALUES (?, 0, 1, ?)")
      ->bind(1, job)
      .bind_blob(2, encode_accumulation(batch[1]))
      .run();
  db.prepare("INSERT INTO pending_results VALUES (?, 0, 3, ?, 0)")
      ->bind(1, job)
      .bind_blob(2, encode_accumulation(batch[3]))
      .run();

  migrate(db, 0);
  EXPECT_EQ(count_rows(db, "SELECT COUNT(*) FROM sqlite_schema WHERE name IN"
                           " ('merged_results', 'pending_results')"),
            0);
  ResultsTable results(db);
  EXPECT_EQ(results.count(job), 2);
  EXPECT_EQ(results.first_merged(job, 0, 2), 1u);
  EXPECT_EQ(results.find(job, 0, 3), encode_accumulation(batch[3]));

  TileMerger merger(db, clock, 0);  // no cache: the sum is rebuilt from the rows
  merger.checkpoint_job(job);
  Accumulation expected(rect);
  expected.merge(batch[0]);
  expected.merge(batch[1]);
  EXPECT_EQ(decode_accumulation(jobs.tiles(job)[0].accumulation), expected);
  EXPECT_EQ(results.count(job), 1);  // batch 3 still waits
  EXPECT_EQ(results.find(job, 0, 3), encode_accumulation(batch[3]));
}

// Migration 9 moves `results` into a rowid table (blobs out of the key's b-tree, the key a
// unique index of integers): every row moves over unchanged and a duplicate is still refused.
TEST(ResultsTable, Migration9KeepsEveryRowAndTheKeyUnique) {
  Database db(":memory:");
  ASSERT_EQ(migrate(db, 0, 8), 8);
  JobStore jobs(db);
  const int64_t job = create_migrated_job(jobs, 'r', 8);
  const TileRect rect{0, 0, 4, 4};
  ResultsTable results(db);
  for (uint32_t tile : {1u, 0u}) {
    for (uint32_t b : {3u, 1u, 2u}) {
      results.append(job, tile, b, encode_accumulation(StoreFixture::synthetic(rect, b + tile, 1)));
    }
  }
  migrate(db, 0);
  EXPECT_EQ(count_rows(db, "SELECT COUNT(*) FROM sqlite_schema WHERE name = 'results' AND"
                           " sql NOT LIKE '%WITHOUT ROWID%'"),
            1);
  EXPECT_EQ(results.count(job), 6);
  for (uint32_t tile : {0u, 1u}) {
    for (uint32_t b : {1u, 2u, 3u}) {
      EXPECT_EQ(results.find(job, tile, b),
                encode_accumulation(StoreFixture::synthetic(rect, b + tile, 1)));
    }
  }
  EXPECT_EQ(results.first_merged(job, 1, 3), 1u);
  EXPECT_THROW(results.append(job, 0, 2, "again"), SqliteError);  // one row per result
  EXPECT_EQ(results.count(job), 6);
  jobs.cancel(job, 0);
  jobs.remove(job);  // the rows go with the job's tiles (ON DELETE CASCADE)
  EXPECT_EQ(count_rows(db, "SELECT COUNT(*) FROM results"), 0);
}

}  // namespace
}  // namespace tessera::server
