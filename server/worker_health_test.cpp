// Worker health beyond failures: NaN/Inf samples counted per worker and reported past a
// threshold; and the store's start-up integrity check.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>

#include "accum/accumulation_codec.h"
#include "coordinator.h"
#include "store/integrity.h"
#include "store_fixture.h"

namespace tessera::server {
namespace {

using testing::StoreFixture;

/// Leases the worker's next unit and delivers a result of `spp` samples per pixel of which
/// `nan` and `inf` were dropped in all.
void deliver(StoreFixture& f, int64_t worker, uint32_t spp, uint64_t nan, uint64_t inf) {
  const Lease lease = *f.book.lease_next(worker);
  const TileRect rect = *f.jobs.tile_rect(lease.job_id, lease.tile);
  Accumulation acc = StoreFixture::synthetic(rect, lease.batch, spp);
  acc.nan_dropped = nan;
  acc.inf_dropped = inf;
  ASSERT_EQ(lease.worker_id, worker);
  ASSERT_TRUE(f.merger.accept(testing::result_for(lease, acc), acc).accepted);
}

TEST(WorkerHealth, NanAndInfSamplesAreCountedPerWorkerAndReportedPastTheThreshold) {
  StoreFixture f;
  f.make_job(64, 64, 64, 16, 4);  // one 64x64 tile, 4 batches of 4 spp: 16384 samples per unit
  const int64_t good = f.make_worker("good"), bad = f.make_worker("bad");
  deliver(f, good, 4, 1, 0);     // 1 of 16385: 0.006 %
  deliver(f, bad, 4, 300, 200);  // 500 of 16884: 3 %
  const WorkerRecord g = *f.workers.get(good), b = *f.workers.get(bad);
  EXPECT_EQ(g.samples_returned, 64u * 64u * 4u + 1u);
  EXPECT_EQ(g.nan_dropped, 1u);
  EXPECT_EQ(b.nan_dropped, 300u);
  EXPECT_EQ(b.inf_dropped, 200u);
  EXPECT_EQ(health_warning(g, 1e-3), "");
  const std::string warning = health_warning(b, 1e-3);
  EXPECT_NE(warning.find("NaN/Inf"), std::string::npos) << warning;
  EXPECT_NE(warning.find("300 NaN, 200 Inf"), std::string::npos) << warning;
  EXPECT_EQ(health_warning(b, 0.05), "");  // a looser threshold does not report it
  // Too few samples to judge: nothing reported yet.
  WorkerRecord fresh = b;
  fresh.samples_returned = kMinSamplesToJudge - 1;
  EXPECT_EQ(health_warning(fresh, 1e-3), "");
}

std::filesystem::path temp_db(const std::string& name) {
  return std::filesystem::temp_directory_path() /
         ("tessera-" + name + "-" + std::to_string(::getpid()) + ".db");
}

void remove_db(const std::filesystem::path& path) {
  for (const char* suffix : {"", "-wal", "-shm"}) {
    std::error_code ec;
    std::filesystem::remove(path.string() + suffix, ec);
  }
}

TEST(StoreIntegrity, AHealthyStorePassesAndCheckpointEmptiesTheWal) {
  const auto path = temp_db("healthy");
  remove_db(path);
  {
    Database db(path.string());
    migrate(db, 0);
    EXPECT_NO_THROW(check_integrity(db, path.string()));
    db.exec(
        "INSERT INTO workers (name, threads, isa, version, registered_unix_ms, last_seen_unix_ms)"
        " VALUES ('w', 1, 'avx2', '0', 0, 0)");
    EXPECT_TRUE(checkpoint_wal(db));
    EXPECT_EQ(std::filesystem::file_size(path.string() + "-wal"), 0u);
  }
  remove_db(path);
}

// Start-up checks the whole file only when the last server did not stop cleanly: the mark is
// taken (and cleared, durably) by every start, so a crash after it is seen by the next one.
TEST(StoreIntegrity, OnlyACleanShutdownLetsTheNextStartSkipTheCheck) {
  const auto path = temp_db("clean-mark");
  remove_db(path);
  {
    Database db(path.string());
    migrate(db, 0);
    EXPECT_FALSE(take_clean_shutdown_mark(db, path.string()));  // a new store: check it
    leave_clean_shutdown_mark(db);
    EXPECT_TRUE(checkpoint_wal(db));
  }
  {
    Database db(path.string());  // the next start after a clean shutdown
    EXPECT_TRUE(take_clean_shutdown_mark(db, path.string()));
    // ...then killed: nothing marks the store clean again.
  }
  {
    Database db(path.string());
    EXPECT_FALSE(take_clean_shutdown_mark(db, path.string()));
  }
  remove_db(path);
}

// A server stopped cleanly (Coordinator::checkpoint last) leaves the mark; one destroyed without
// it (as a crash would) does not.
TEST(StoreIntegrity, TheCoordinatorsCheckpointLeavesTheMark) {
  const auto path = temp_db("coordinator-mark");
  remove_db(path);
  testing::FakeClock clock;
  CoordinatorConfig config;
  config.db_path = path.string();
  config.output_dir = std::filesystem::temp_directory_path() / "tessera-mark-test";
  { Coordinator(config, clock).checkpoint(); }
  {
    Database db(path.string());
    EXPECT_TRUE(take_clean_shutdown_mark(db, path.string()));
  }
  { Coordinator crashed(config, clock); }  // no checkpoint()
  {
    Database db(path.string());
    EXPECT_FALSE(take_clean_shutdown_mark(db, path.string()));
  }
  remove_db(path);
}

TEST(StoreIntegrity, ADamagedStoreIsRefusedWithAClearMessage) {
  const auto path = temp_db("damaged");
  remove_db(path);
  {
    Database db(path.string());
    migrate(db, 0);
    for (int i = 0; i < 200; ++i) {
      db.exec(
          "INSERT INTO workers (name, threads, isa, version, registered_unix_ms,"
          " last_seen_unix_ms) VALUES ('worker with a long name to fill pages', 1, 'avx2',"
          " '0', 0, 0)");
    }
    checkpoint_wal(db);
  }
  // Overwrite the middle of the file (b-tree pages) with garbage, as a torn disk would.
  const auto size = std::filesystem::file_size(path);
  ASSERT_GT(size, 3u * 4096u);
  {
    std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(std::streamoff(4096 + 100));
    const std::string garbage(size - 4096 - 200, '\x5a');
    file.write(garbage.data(), std::streamsize(garbage.size()));
  }
  std::string message;
  try {
    Database db(path.string());
    check_integrity(db, path.string());
  } catch (const StoreCorrupt& e) {
    message = e.what();
  } catch (const SqliteError& e) {
    ASSERT_TRUE(is_corruption(e)) << e.what();
    message = corrupt_store_message(path.string(), e.what());
  }
  EXPECT_NE(message.find("is damaged"), std::string::npos) << message;
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
  EXPECT_NE(message.find("restore a backup"), std::string::npos) << message;
  remove_db(path);
}

/// A store left as a crash leaves it (no clean-shutdown mark) holding `workers` worker rows,
/// which start-up never reads, written last so that they fill the file's last pages; returns
/// the page size.
int64_t make_unclean_store(const std::filesystem::path& path, int workers) {
  remove_db(path);
  Database db(path.string());
  migrate(db, 0);
  {
    Transaction t(db);
    for (int i = 0; i < workers; ++i) {
      db.exec(
          "INSERT INTO workers (name, threads, isa, version, registered_unix_ms,"
          " last_seen_unix_ms) VALUES ('worker with a long name to fill pages', 1, 'avx2',"
          " '0', 0, 0)");
    }
    t.commit();
  }
  EXPECT_TRUE(checkpoint_wal(db));
  auto q = db.prepare("PRAGMA page_size");
  EXPECT_TRUE(q->step());
  return q->int64(0);
}

CoordinatorConfig config_for(const std::filesystem::path& path) {
  CoordinatorConfig config;
  config.db_path = path.string();
  config.output_dir = std::filesystem::temp_directory_path() / "tessera-check-test";
  return config;
}

// After an unclean stop the whole-file check runs beside the server, not before it: a store
// damaged where start-up does not read is opened and served, then the check finds the damage,
// and the server says so (store_damage, the observer), stops leasing and is no longer ready;
// its clean shutdown leaves no mark, so the next start checks again.
TEST(StoreIntegrity, DamageFoundByTheBackgroundCheckStopsLeasingAndIsReported) {
  const auto path = temp_db("background-damaged");
  const int64_t page = make_unclean_store(path, 3000);
  const auto size = std::filesystem::file_size(path);
  ASSERT_GT(size, uint64_t(page) * 40);
  {
    // Garbage over the last 8 pages (leaves of the workers table), as a torn disk would leave.
    std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(std::streamoff(size - uint64_t(page) * 8));
    const std::string garbage(size_t(page) * 8, '\x5a');
    file.write(garbage.data(), std::streamsize(garbage.size()));
  }
  testing::FakeClock clock;
  Coordinator coordinator(config_for(path), clock);  // start-up does not read those pages
  EXPECT_EQ(coordinator.resume(), 0);
  std::string observed;
  coordinator.set_damage_observer([&](const std::string& m) { observed = m; });
  ASSERT_EQ(coordinator.wait_for_store_check(), IntegrityState::damaged);
  const std::string damage = coordinator.store_damage();
  EXPECT_NE(damage.find("is damaged"), std::string::npos) << damage;
  EXPECT_NE(damage.find(path.string()), std::string::npos) << damage;
  EXPECT_NE(damage.find("quick_check"), std::string::npos) << damage;
  EXPECT_EQ(observed, damage);  // set before or after the check ended: called once either way
  EXPECT_FALSE(coordinator.store_ready());
  EXPECT_TRUE(coordinator.changes().stopped());
  EXPECT_TRUE(coordinator.lease_units(1, 16, std::chrono::milliseconds(0), nullptr).empty());
  coordinator.checkpoint();  // a clean stop, but the store is damaged: no mark
  {
    Database db(path.string());
    EXPECT_FALSE(take_clean_shutdown_mark(db, path.string()));
  }
  remove_db(path);
}

// The same store undamaged: the check passes in the background and the clean stop leaves the
// mark; a clean start runs no check at all.
TEST(StoreIntegrity, AHealthyStoreAfterAnUncleanStopPassesTheBackgroundCheck) {
  const auto path = temp_db("background-healthy");
  make_unclean_store(path, 3000);
  testing::FakeClock clock;
  {
    Coordinator coordinator(config_for(path), clock);
    coordinator.set_damage_observer([](const std::string& m) { ADD_FAILURE() << m; });
    EXPECT_EQ(coordinator.wait_for_store_check(), IntegrityState::ok);
    EXPECT_EQ(coordinator.store_damage(), "");
    EXPECT_TRUE(coordinator.store_ready());
    EXPECT_FALSE(coordinator.changes().stopped());
    coordinator.checkpoint();
  }
  {
    Coordinator coordinator(config_for(path), clock);
    EXPECT_EQ(coordinator.store_check(), std::nullopt);  // stopped cleanly: nothing to check
  }
  remove_db(path);
}

// A check stopped before it ends (a shutdown right after start-up) never reports damage it did
// not find, and leaves no mark unless it had passed: the next start checks again.
TEST(StoreIntegrity, AStoppedCheckLeavesTheMarkOnlyWhenItHadPassed) {
  const auto path = temp_db("background-stopped");
  make_unclean_store(path, 3000);
  testing::FakeClock clock;
  std::optional<IntegrityState> state;
  {
    Coordinator coordinator(config_for(path), clock);
    coordinator.checkpoint();  // stops the check wherever it is
    state = coordinator.store_check();
    EXPECT_EQ(coordinator.store_damage(), "");
  }
  ASSERT_TRUE(state == IntegrityState::ok || state == IntegrityState::interrupted)
      << integrity_state_name(*state);
  {
    Database db(path.string());
    EXPECT_EQ(take_clean_shutdown_mark(db, path.string()), state == IntegrityState::ok);
  }
  // Stopped before its thread opened its connection, or while it reads: the same rule.
  for (int i = 0; i < 20; ++i) {
    BackgroundIntegrityCheck check(path.string(), [](IntegrityState s, const std::string& m) {
      EXPECT_NE(s, IntegrityState::damaged) << m;
    });
    check.stop();
    EXPECT_NE(check.state(), IntegrityState::checking);
    EXPECT_EQ(check.message(), "");
  }
  remove_db(path);
}

}  // namespace
}  // namespace tessera::server

namespace tessera::server {
namespace {

TEST(GracefulShutdown, StopLeasingRefusesNewLeasesButCommitsResultsInFlight) {
  testing::FakeClock clock;
  CoordinatorConfig config;
  config.db_path = ":memory:";
  config.output_dir = std::filesystem::temp_directory_path() /
                      ("tessera-shutdown-test-" + std::to_string(::getpid()));
  Coordinator coordinator(config, clock);
  v1::SceneBundle bundle;
  bundle.set_scene_file("scene.json");
  auto* file = bundle.add_files();
  file->set_path("scene.json");
  std::ifstream in(std::string(TESSERA_TEST_DATA_DIR) + "/tiny.json");
  file->set_data(std::string(std::istreambuf_iterator<char>(in), {}));
  v1::JobRequestOptions options;
  options.set_spp(2);
  options.set_batch_spp(1);  // one 16x16 tile, 2 batches
  const JobRecord job = coordinator.submit(bundle, options, 0, "test");
  const int64_t worker = coordinator.register_worker({"w", 1, "avx2", "0"});
  const std::optional<LeasedUnit> unit = coordinator.lease(worker, std::chrono::milliseconds(0), {});
  ASSERT_TRUE(unit);

  coordinator.stop_leasing();
  // A long poll returns at once with no work, and nothing new is leased.
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(coordinator.lease(worker, std::chrono::milliseconds(60'000), {}), std::nullopt);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(30));
  const int64_t other = coordinator.register_worker({"other", 1, "avx2", "0"});
  EXPECT_EQ(coordinator.lease(other, std::chrono::milliseconds(0), {}), std::nullopt);
  // The unit in flight still delivers, and its result is committed.
  UnitResult r;
  r.worker_id = worker;
  r.lease_id = unit->lease.lease_id;
  r.job_id = unit->lease.job_id;
  r.tile = unit->lease.tile;
  r.batch = unit->lease.batch;
  r.encoded = encode_accumulation(StoreFixture::synthetic(unit->rect, unit->lease.batch, 1));
  r.isa = "avx2";
  EXPECT_TRUE(coordinator.upload(r).accepted);
  EXPECT_EQ(coordinator.job(job.id).counters.results_merged, 1u);
  EXPECT_TRUE(coordinator.checkpoint());
  std::filesystem::remove_all(config.output_dir);
}

}  // namespace
}  // namespace tessera::server
