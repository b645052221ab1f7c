// The SQLite layer and the job store, on :memory: (and a temporary file where WAL or locking is
// the point).
#include <gtest/gtest.h>

#include <filesystem>
#include <unistd.h>

#include "farm_error.h"
#include "job_store.h"
#include "store/migrations.h"
#include "store/sqlite.h"
#include "store_fixture.h"

namespace tessera::server {
namespace {

/// The newest `limit` jobs (JobStore::list's first page).
std::vector<JobRecord> newest(JobStore& jobs, uint32_t limit) {
  JobQuery query;
  query.limit = limit;
  return jobs.list(query).jobs;
}

using testing::StoreFixture;

/// A temporary folder for database files, removed with its contents when the test ends.
class TempFolder {
 public:
  TempFolder()
      : path_(std::filesystem::temp_directory_path() /
              ("tessera-store-test-" + std::to_string(getpid()))) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempFolder() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  std::filesystem::path file(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

TEST(Sqlite, MigrationsRunOnceAndAreRecorded) {
  Database db(":memory:");
  EXPECT_EQ(schema_version(db), 0);
  const int version = migrate(db, 1000);
  EXPECT_EQ(version, schema_migrations().back().version);
  EXPECT_EQ(migrate(db, 2000), version);  // nothing left to apply
  auto q = db.prepare("SELECT COUNT(*), MIN(applied_unix_ms) FROM schema_migrations");
  ASSERT_TRUE(q->step());
  EXPECT_EQ(q->int64(0), int64_t(schema_migrations().size()));
  EXPECT_EQ(q->int64(1), 1000);
}

// Increasing from 1; a gap is allowed (migrate applies each by number), so that two changes
// made side by side can each take their own number.
TEST(Sqlite, MigrationsAreNumberedInIncreasingOrder) {
  int previous = 0;
  ASSERT_FALSE(schema_migrations().empty());
  EXPECT_EQ(schema_migrations().front().version, 1);
  for (const Migration& m : schema_migrations()) {
    EXPECT_GT(m.version, previous) << m.name;
    previous = m.version;
  }
}

TEST(Sqlite, RefusesADatabaseFromANewerVersion) {
  Database db(":memory:");
  migrate(db, 0);
  db.exec("INSERT INTO schema_migrations VALUES (999, 'from the future', 0)");
  EXPECT_THROW(migrate(db, 0), std::runtime_error);
}

TEST(Sqlite, FileDatabaseIsWalWithForeignKeys) {
  const TempFolder folder;
  Database db(folder.file("wal.db").string());
  {
    auto q = db.prepare("PRAGMA journal_mode");
    ASSERT_TRUE(q->step());
    EXPECT_EQ(q->text(0), "wal");
  }
  auto q = db.prepare("PRAGMA foreign_keys");
  ASSERT_TRUE(q->step());
  EXPECT_EQ(q->int64(0), 1);
}

TEST(Sqlite, ErrorsCarryResultCodes) {
  Database db(":memory:");
  migrate(db, 0);
  // A unit of a job that does not exist: the foreign key refuses it.
  try {
    db.prepare("INSERT INTO units (job_id, tile, batch, state) VALUES (42, 0, 0, 'queued')")->run();
    FAIL() << "foreign key not enforced";
  } catch (const SqliteError& e) {
    EXPECT_EQ(e.code(), SQLITE_CONSTRAINT_FOREIGNKEY);
    EXPECT_EQ(e.primary_code(), SQLITE_CONSTRAINT);
  }
  try {
    db.exec("SELEKT 1");
    FAIL() << "syntax error not reported";
  } catch (const SqliteError& e) {
    EXPECT_EQ(e.primary_code(), SQLITE_ERROR);
  }
}

TEST(Sqlite, LeaseIdIsSetExactlyWhenLeased) {
  StoreFixture f;
  const int64_t job = f.make_job(8, 8, 8, 1, 1);
  // A unit's row is born leased, with its lease id; released, it is queued without one.
  const int64_t worker = f.make_worker();
  const Lease lease = *f.book.lease_next(worker);
  ASSERT_TRUE(f.leases.release(worker, lease.lease_id, ReleaseReason::shutdown, "").released);
  EXPECT_THROW(f.db.prepare("UPDATE units SET state = 'leased' WHERE job_id = ?")->bind(1, job).run(),
               SqliteError);
  EXPECT_THROW(f.db.prepare("UPDATE units SET lease_id = 'x' WHERE job_id = ?")->bind(1, job).run(),
               SqliteError);
}

TEST(Sqlite, TransactionRollsBackUnlessCommitted) {
  Database db(":memory:");
  db.exec("CREATE TABLE t (v INTEGER)");
  {
    Transaction tx(db);
    db.prepare("INSERT INTO t VALUES (1)")->run();
  }
  {
    Transaction tx(db);
    db.prepare("INSERT INTO t VALUES (2)")->run();
    tx.commit();
  }
  auto q = db.prepare("SELECT COUNT(*), SUM(v) FROM t");
  ASSERT_TRUE(q->step());
  EXPECT_EQ(q->int64(0), 1);
  EXPECT_EQ(q->int64(1), 2);
}

TEST(Sqlite, BlobsRoundTripBytesExactly) {
  Database db(":memory:");
  db.exec("CREATE TABLE b (data BLOB)");
  const std::string bytes("\0\1\2\xff zero\0end", 12);
  db.prepare("INSERT INTO b VALUES (?)")->bind_blob(1, bytes).run();
  db.prepare("INSERT INTO b VALUES (?)")->bind_blob(1, "").run();
  auto q = db.prepare("SELECT data, data IS NULL FROM b ORDER BY rowid");
  ASSERT_TRUE(q->step());
  EXPECT_EQ(q->blob(0), bytes);
  ASSERT_TRUE(q->step());
  EXPECT_EQ(q->blob(0), "");
  EXPECT_EQ(q->int64(1), 0);  // an empty blob, not NULL
}

TEST(Sqlite, SecondWriterGetsBusyAfterItsTimeout) {
  const TempFolder folder;
  const std::string path = folder.file("busy.db").string();
  Database first(path);
  first.exec("CREATE TABLE t (v INTEGER)");
  Database second(path, /*busy_timeout_ms=*/50);
  Transaction holding(first);
  try {
    Transaction blocked(second);
    FAIL() << "BEGIN IMMEDIATE did not wait for the writer";
  } catch (const SqliteError& e) {
    EXPECT_EQ(e.primary_code(), SQLITE_BUSY);
  }
}

TEST(JobStore, CreatesTilesAndUnitsOfThePlan) {
  StoreFixture f;
  // 100x50 in 32-pixel tiles: 4 x 2 tiles; 10 spp in batches of 4: 3 batches (4, 4, 2).
  const int64_t id = f.make_job(100, 50, 32, 10, 4, /*priority=*/7);
  const std::optional<JobRecord> job = f.jobs.get(id);
  ASSERT_TRUE(job);
  EXPECT_EQ(job->state, JobState::queued);
  EXPECT_EQ(job->priority, 7);
  EXPECT_EQ(job->tile_count, 8u);
  EXPECT_EQ(job->batch_count, 3u);
  EXPECT_EQ(job->units_total, 24u);
  EXPECT_EQ(job->options.width, 100);
  EXPECT_EQ(job->options.batch_spp, 4u);
  EXPECT_EQ(job->spp_merged, 0u);
  EXPECT_EQ(job->progress(), 0.0);
  const std::vector<TileRecord> tiles = f.tiles(id);
  ASSERT_EQ(tiles.size(), 8u);
  EXPECT_EQ(tiles[3].rect, (TileRect{96, 0, 100, 32}));
  EXPECT_EQ(tiles[7].rect, (TileRect{96, 32, 100, 50}));
  // The units come into being when leased: none has a row yet, every tile has 3 batches to go.
  auto q = f.db.prepare(
      "SELECT (SELECT COUNT(*) FROM units WHERE job_id = ?1), COUNT(*), MIN(next_lease),"
      " MAX(next_lease), MIN(lease_end), MAX(lease_end) FROM tile_queue WHERE job_id = ?1");
  q->bind(1, id);
  ASSERT_TRUE(q->step());
  EXPECT_EQ(q->int64(0), 0);
  EXPECT_EQ(q->int64(1), 8);
  EXPECT_EQ(q->int64(2), 0);
  EXPECT_EQ(q->int64(3), 0);
  EXPECT_EQ(q->int64(4), 3);
  EXPECT_EQ(q->int64(5), 3);
  EXPECT_FALSE(job->complete);
}

int64_t rows(Database& db, const std::string& table) {
  auto q = db.prepare("SELECT COUNT(*) FROM " + table);
  EXPECT_TRUE(q->step());
  return q->int64(0);
}

// Lazy units: a submit writes O(tiles) rows whatever the spp. 2^20 batches of 1 spp
// on 4 tiles are 4,194,304 units, the store's limit; the submit writes 1 job, 4 tiles and 4
// queue rows, and leasing creates a unit's row only when it is leased.
TEST(JobStore, ASubmitWritesRowsPerTileNotPerUnit) {
  StoreFixture f;
  const int64_t id = f.make_job(64, 64, 32, uint32_t(1) << 20, 1);
  EXPECT_EQ(f.jobs.get(id)->units_total, 4194304u);
  EXPECT_EQ(rows(f.db, "jobs"), 1);
  EXPECT_EQ(rows(f.db, "tiles"), 4);
  EXPECT_EQ(rows(f.db, "tile_queue"), 4);
  EXPECT_EQ(rows(f.db, "units"), 0);
  const int64_t w = f.make_worker();
  for (uint32_t i = 0; i < 6; ++i) {
    const Lease l = *f.book.lease_next(w);
    EXPECT_EQ(l.batch, i / 4);
    EXPECT_EQ(l.tile, i % 4);
    const Accumulation acc = StoreFixture::synthetic(f.tiles(id)[l.tile].rect, l.batch, 1);
    ASSERT_TRUE(f.merger.accept(testing::result_for(l, acc), acc).accepted);
  }
  EXPECT_EQ(rows(f.db, "units"), 6);
  // Cancelling ends the units without a row too: nothing is left to lease, the job is final.
  ASSERT_EQ(f.jobs.cancel(id, 0), CancelOutcome::cancelled);
  EXPECT_FALSE(units_left(f.db, id));
  EXPECT_EQ(f.book.lease_next(w), std::nullopt);
}

// A store written before lazy units (schema 5) has a row for every unit of its jobs. After the
// migration those jobs lease the same units in the same order, each once, and finish.
TEST(JobStore, JobsStoredWithEveryUnitRowKeepWorkingAfterTheMigration) {
  testing::FakeClock clock;
  Database db(":memory:");
  ASSERT_EQ(migrate(db, 0, 5), 5);
  const std::string sha(64, 'd');
  db.exec("INSERT INTO bundles VALUES ('" + sha + "', 's.json', x'00', 1, 0)");
  // 16x8 in 8-px tiles (2 tiles), 3 spp in fixed batches of 1, half-leased as a schema-5 server
  // left it: (batch 0, tile 0) done and merged, (0, 1) leased, the rest queued.
  db.exec(
      "INSERT INTO jobs (state, priority, bundle_sha256, scene_file, width, height, spp,"
      " max_depth, seed, tile_size, batch_spp, isa, tile_count, batch_count, units_total,"
      " submitted_unix_ms, started_unix_ms, units_done, results_merged) VALUES ('running', 0, '" +
      sha + "', 's.json', 16, 8, 3, -1, 0, 8, 1, '', 2, 3, 6, 0, 1, 1, 1)");
  const Accumulation first = StoreFixture::synthetic({0, 0, 8, 8}, 0, 1);
  {
    auto q = db.prepare(
        "INSERT INTO tiles (job_id, tile, x0, y0, x1, y1, next_batch, accumulation, spp)"
        " VALUES (1, ?, ?, 0, ?, 8, ?, ?, ?)");
    q->bind(1, 0).bind(2, 0).bind(3, 8).bind(4, 1).bind_blob(5, encode_accumulation(first));
    q->bind(6, 1).run();
    q->reset();
    q->bind(1, 1).bind(2, 8).bind(3, 16).bind(4, 0).bind_null(5).bind(6, 0).run();
  }
  db.exec(
      "INSERT INTO workers (name, threads, isa, version, registered_unix_ms, last_seen_unix_ms)"
      " VALUES ('old', 1, 'avx2', '0', 0, 0)");
  for (int batch = 0; batch < 3; ++batch) {
    for (int tile = 0; tile < 2; ++tile) {
      const bool done = batch == 0 && tile == 0, leased = batch == 0 && tile == 1;
      db.prepare(
            "INSERT INTO units (job_id, tile, batch, state, lease_id, worker_id,"
            " lease_expires_unix_ms) VALUES (1, ?, ?, ?, ?, ?, ?)")
          ->bind(1, tile)
          .bind(2, batch)
          .bind(3, done ? "done" : leased ? "leased" : "queued")
          .bind(4, leased ? std::optional<std::string>("old-lease") : std::nullopt)
          .bind(5, leased ? std::optional<int64_t>(1) : std::nullopt)
          .bind(6, leased ? std::optional<int64_t>(5) : std::nullopt)
          .run();
    }
  }
  migrate(db, 0);
  EXPECT_EQ(rows(db, "tile_queue"), 2);
  JobStore jobs(db);
  WorkerRegistry workers(db);
  LeaseTable leases(db, jobs, clock, 10'000);
  testing::BookLeaser scheduler(db, jobs, leases, clock);
  TileMerger merger(db, clock);
  EXPECT_EQ(leases.revoke_all(), 1);  // as at start-up: (0, 1) back in the queue
  std::vector<std::pair<uint32_t, uint32_t>> order;
  const int64_t w = workers.register_worker({"new", 1, "avx2", "1"}, 0);
  while (const std::optional<Lease> l = scheduler.lease_next(w)) {
    order.emplace_back(l->batch, l->tile);
    const Accumulation acc =
        StoreFixture::synthetic({int(l->tile) * 8, 0, int(l->tile) * 8 + 8, 8}, l->batch, 1);
    ASSERT_TRUE(merger.accept(testing::result_for(*l, acc), acc).accepted);
  }
  EXPECT_EQ(order, (std::vector<std::pair<uint32_t, uint32_t>>{
                       {0, 1}, {1, 0}, {1, 1}, {2, 0}, {2, 1}}));
  EXPECT_EQ(rows(db, "units"), 6);  // no unit created twice
  const JobRecord r = *jobs.get(1);
  EXPECT_TRUE(r.complete);
  EXPECT_EQ(r.counters.results_merged, 6u);
  EXPECT_EQ(r.spp_merged, 3u);
  EXPECT_TRUE(jobs.finish(1, "a.exr", "a.png", 10));
}

TEST(JobStore, StoresEachBundleOnce) {
  StoreFixture f;
  NewJob job;
  job.bundle_sha256 = std::string(64, 'b');
  job.scene_file = "s.json";
  job.bundle_bytes = "bytes";
  job.options.width = job.options.height = job.options.tile_size = 4;
  job.options.spp = job.options.batch_spp = 1;
  f.jobs.create(job, 0);
  f.jobs.create(job, 1);
  auto q = f.db.prepare("SELECT COUNT(*) FROM bundles");
  ASSERT_TRUE(q->step());
  EXPECT_EQ(q->int64(0), 1);
  EXPECT_EQ(f.jobs.bundle_bytes(job.bundle_sha256), "bytes");
  EXPECT_EQ(f.jobs.bundle_bytes(std::string(64, 'c')), std::nullopt);
}

TEST(JobStore, RefusesJobsWithTooManyUnits) {
  StoreFixture f;
  try {
    f.make_job(32768, 32768, 1, 1, 1);
    FAIL() << "a job of 2^30 units was accepted";
  } catch (const FarmError& e) {
    EXPECT_EQ(e.code(), ErrorCode::invalid_argument);
    EXPECT_NE(std::string(e.what()).find("--tile or --batch"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(newest(f.jobs, 10).empty());
}

TEST(JobStore, ListsNewestFirst) {
  StoreFixture f;
  const int64_t a = f.make_job(8, 8, 8, 1, 1);
  const int64_t b = f.make_job(8, 8, 8, 1, 1);
  const std::vector<JobRecord> jobs = newest(f.jobs, 10);
  ASSERT_EQ(jobs.size(), 2u);
  EXPECT_EQ(jobs[0].id, b);
  EXPECT_EQ(jobs[1].id, a);
  EXPECT_EQ(newest(f.jobs, 1).size(), 1u);
}

TEST(JobStore, CancelRevokesUnitsAndIsFinal) {
  StoreFixture f;
  const int64_t job = f.make_job(16, 16, 8, 4, 2);
  const int64_t worker = f.make_worker();
  const std::optional<Lease> lease = f.book.lease_next(worker);
  ASSERT_TRUE(lease);
  EXPECT_EQ(f.jobs.cancel(job, f.clock.now_unix_ms()), CancelOutcome::cancelled);
  EXPECT_EQ(f.jobs.get(job)->state, JobState::cancelled);
  EXPECT_EQ(f.jobs.get(job)->counters.units_leased, 0u);
  EXPECT_EQ(f.jobs.cancel(job, 0), CancelOutcome::already_final);
  EXPECT_EQ(f.jobs.cancel(job + 100, 0), CancelOutcome::not_found);
  // The revoked lease cannot be extended, and no unit of the job is handed out any more.
  EXPECT_EQ(f.book.heartbeat(worker, lease->lease_id), std::nullopt);
  EXPECT_EQ(f.book.lease_next(worker), std::nullopt);
  EXPECT_EQ(f.jobs.unfinished(), std::vector<int64_t>{});
}

TEST(JobStore, FailedJobRecordsTheReason) {
  StoreFixture f;
  const int64_t job = f.make_job(8, 8, 8, 1, 1);
  EXPECT_TRUE(f.jobs.fail(job, "disk full", 5));
  EXPECT_EQ(f.jobs.get(job)->state, JobState::failed);
  EXPECT_EQ(f.jobs.get(job)->error, "disk full");
  EXPECT_FALSE(f.jobs.fail(job, "again", 6));
  EXPECT_EQ(f.jobs.get(job)->error, "disk full");
}

TEST(WorkerRegistry, RegistersTouchesAndShowsTheLeasedUnit) {
  StoreFixture f;
  const int64_t a = f.make_worker("a");
  const int64_t b = f.make_worker("b");
  EXPECT_NE(a, b);
  f.clock.advance(500);
  EXPECT_TRUE(f.workers.touch(a, f.clock.now_unix_ms()));
  EXPECT_FALSE(f.workers.touch(b + 10, f.clock.now_unix_ms()));
  const int64_t job = f.make_job(8, 8, 8, 1, 1);
  ASSERT_TRUE(f.book.lease_next(a));
  const std::vector<WorkerRecord> all = f.workers.list();
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[0].id, a);  // most recently seen first
  EXPECT_EQ(all[0].job_id, job);
  EXPECT_EQ(all[1].job_id, std::nullopt);
}

// Seeds are any 64-bit value: SQLite's signed integer holds the bit pattern, and
// every value from 2^63 up reads back as it was written.
TEST(JobStore, SeedsOfEverySixtyFourBitValueRoundTrip) {
  StoreFixture f;
  for (const uint64_t seed : {uint64_t(0), uint64_t(1) << 63, ~uint64_t(0), uint64_t(12345)}) {
    NewJob job;
    job.scene_file = "scene.json";
    job.bundle_bytes = "bundle";
    job.bundle_sha256 = std::string(64, 'b');
    job.options.width = job.options.height = 8;
    job.options.tile_size = 8;
    job.options.spp = job.options.batch_spp = 1;
    job.options.seed = seed;
    const int64_t id = f.jobs.create(job, f.clock.now_unix_ms());
    EXPECT_EQ(f.jobs.get(id)->options.seed, seed);
    EXPECT_EQ(f.jobs.spec(id)->options.seed, seed);
  }
}

}  // namespace
}  // namespace tessera::server
