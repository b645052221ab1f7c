// A full output disk: the job that completes while the disk is full stays done with
// its merged image in the store and says why its files are missing (output_error, no paths);
// `get` answers the final image and writes the files again once space is back, and so does the
// next server start. ENOSPC comes through the output opener's seam
// (CoordinatorConfig::output_opener); an output folder that cannot be created is a folder under a
// regular file. A full database disk: the store at its PRAGMA max_page_count
// (CoordinatorConfig::on_store_open) refuses uploads with SQLITE_FULL while reads, the job list,
// the tile map and the preview still answer, the store reports it cannot write and is not ready,
// and is ready again once a probe write commits.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "accum/accumulation_codec.h"
#include "coordinator.h"
#include "fake_clock.h"
#include "proto_convert.h"
#include "store_fixture.h"
#include "wire/job_json.h"

namespace tessera::server {
namespace {

/// An ImageFileStream, unless the disk is "full": then what a full disk gives (ENOSPC).
struct Disk {
  bool full = false;
  int refused = 0;
  ImageFileOpener opener() {
    return [this](const std::filesystem::path& path, int width, int height, const ImageWriteOptions& options) {
      if (full) {
        ++refused;
        throw std::system_error(ENOSPC, std::generic_category(), path.string());
      }
      return ImageFileStream(path, width, height, options);
    };
  }
};

/// Renders nothing: delivers synthetic results for every unit until the job is done.
void complete(Coordinator& farm, int64_t job_id) {
  const int64_t worker = farm.register_worker({"w", 1, "avx2", "test"});
  for (;;) {
    const std::optional<LeasedUnit> unit =
        farm.lease(worker, std::chrono::milliseconds(0), [] { return false; });
    if (!unit) break;
    const Accumulation acc =
        testing::StoreFixture::synthetic(unit->rect, unit->lease.batch,
                                         unit->sample_end - unit->sample_begin);
    UnitResult r = testing::result_for(unit->lease, acc);
    ASSERT_TRUE(farm.upload(r).accepted);
  }
  ASSERT_EQ(farm.job(job_id).state, JobState::done);
}

TEST(FullDisk, AJobStaysDoneAndItsFilesAreWrittenByTheNextGetOrStart) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("tessera-full-disk-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  const std::string db = (dir / "tessera.db").string();
  std::filesystem::create_directories(dir);
  testing::FakeClock clock;
  Disk disk;
  CoordinatorConfig config;
  config.db_path = db;
  config.output_dir = dir / "outputs";
  config.output_opener = disk.opener();
  int64_t id = 0;
  {
    Coordinator farm(config, clock);
    v1::JobRequestOptions options;
    options.set_spp(4);
    options.set_tile_size(8);
    options.set_batch_spp(2);
    id = farm.submit(testing::tiny_bundle(), options, 0, "test").id;
    disk.full = true;
    complete(farm, id);
    EXPECT_GT(disk.refused, 0);
    JobRecord job = farm.job(id);
    EXPECT_EQ(job.state, JobState::done);
    EXPECT_EQ(job.error, "");
    // Why the files are missing, and no paths to them.
    EXPECT_NE(job.output_error.find(std::generic_category().message(ENOSPC)), std::string::npos)
        << job.output_error;
    EXPECT_EQ(job.output_exr, "");
    EXPECT_EQ(job.output_png, "");
    EXPECT_EQ(farm.jobs(10).front().output_error, job.output_error);
    const OutputFiles where = JobOutput(config.output_dir).files(job);
    EXPECT_FALSE(std::filesystem::exists(where.exr));
    // No half-written or temporary file either.
    EXPECT_TRUE(!std::filesystem::exists(dir / "outputs") || std::filesystem::is_empty(dir / "outputs"));

    // Still full: `get` answers the final image from the store.
    JobImage image = farm.image(id, "exr");
    EXPECT_TRUE(image.final);
    EXPECT_EQ(image.spp, 4u);
    EXPECT_FALSE(image.bytes.empty());
    EXPECT_FALSE(std::filesystem::exists(where.exr));
    EXPECT_NE(farm.job(id).output_error, "");

    // Space is back: the next `get` writes both files, and the job names them.
    disk.full = false;
    image = farm.image(id, "png");
    EXPECT_TRUE(image.final);
    job = farm.job(id);
    EXPECT_EQ(job.output_error, "");
    EXPECT_EQ(job.output_exr, where.exr.string());
    EXPECT_EQ(job.output_png, where.png.string());
    EXPECT_TRUE(std::filesystem::exists(job.output_exr));
    EXPECT_TRUE(std::filesystem::exists(job.output_png));
    std::filesystem::remove(job.output_exr);
    std::filesystem::remove(job.output_png);
  }
  {
    // A restart writes what is missing.
    Coordinator farm(config, clock);
    farm.resume();
    const JobRecord job = farm.job(id);
    EXPECT_EQ(job.state, JobState::done);
    EXPECT_TRUE(std::filesystem::exists(job.output_exr));
    EXPECT_TRUE(std::filesystem::exists(job.output_png));
  }
  std::filesystem::remove_all(dir);
}

std::filesystem::path full_disk_fresh_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("tessera-full-disk-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

TEST(FullDisk, AnOutputFolderThatCannotBeCreatedIsShownWithTheJobUntilTheFilesExist) {
  const auto dir = full_disk_fresh_dir("folder");
  // A folder under a regular file cannot be created, whoever runs the test (root included).
  std::ofstream(dir / "not-a-folder") << "x";
  testing::FakeClock clock;
  CoordinatorConfig config;
  config.db_path = ":memory:";
  config.output_dir = dir / "not-a-folder" / "outputs";
  Coordinator farm(config, clock);
  v1::JobRequestOptions options;
  options.set_spp(2);
  options.set_tile_size(8);
  options.set_batch_spp(2);
  const int64_t id = farm.submit(testing::tiny_bundle(), options, 0, "test").id;
  complete(farm, id);

  const JobRecord job = farm.job(id);
  EXPECT_EQ(job.state, JobState::done);
  EXPECT_EQ(job.error, "");
  const std::string folder = (dir / "not-a-folder" / "outputs").string();
  EXPECT_NE(job.output_error.find(folder + ": cannot create: "), std::string::npos)
      << job.output_error;
  EXPECT_EQ(job.output_exr, "");
  EXPECT_EQ(job.output_png, "");
  // The job's one JSON (status --json, /api/jobs/{id}): the key, and no paths.
  const nlohmann::json j = wire::job_json(to_proto(job));
  EXPECT_EQ(j["output_error"], job.output_error);
  EXPECT_EQ(j["output_exr"], "");
  EXPECT_EQ(j["error"], "");

  // The folder can be made now: the next `get` writes the files and the error goes.
  std::filesystem::remove(dir / "not-a-folder");
  EXPECT_TRUE(farm.image(id, "exr").final);
  const JobRecord written = farm.job(id);
  EXPECT_EQ(written.output_error, "");
  EXPECT_TRUE(std::filesystem::exists(written.output_exr));
  EXPECT_TRUE(std::filesystem::exists(written.output_png));
  EXPECT_EQ(wire::job_json(to_proto(written))["output_error"], "");
  std::filesystem::remove_all(dir);
}

/// The store's page count now (every page of the file and its WAL).
int64_t full_disk_page_count(Database& db) {
  return db.prepare("PRAGMA page_count")->first_row([](const Statement& q) { return q.int64(0); })
      .value_or(0);
}

TEST(FullDisk, AFullStoreKeepsReadsWorkingAndSaysItCannotWriteUntilItCan) {
  const auto dir = full_disk_fresh_dir("store");
  testing::FakeClock clock;
  Database* db = nullptr;
  CoordinatorConfig config;
  config.db_path = (dir / "tessera.db").string();
  config.output_dir = dir / "outputs";
  config.on_store_open = [&db](Database& opened) { db = &opened; };
  Coordinator farm(config, clock);
  ASSERT_NE(db, nullptr);
  const int64_t id = farm.submit(testing::tiny_bundle(), testing::small_units(), 0, "test").id;
  const int64_t worker = farm.register_worker({"w", 1, "avx2", "test"});
  EXPECT_EQ(farm.store_write_error(), "");
  EXPECT_TRUE(farm.store_ready());

  // Merge a few results, then the disk is full: the file may not grow by a page.
  auto deliver = [&](int units) {
    int refused = 0;
    for (int i = 0; i < units; ++i) {
      const std::optional<LeasedUnit> unit =
          farm.lease(worker, std::chrono::milliseconds(0), [] { return false; });
      if (!unit) break;
      const Accumulation acc = testing::StoreFixture::synthetic(
          unit->rect, unit->lease.batch, unit->sample_end - unit->sample_begin);
      try {
        if (!farm.upload(testing::result_for(unit->lease, acc)).accepted) ++refused;
      } catch (const std::exception&) {
        ++refused;
      }
    }
    return refused;
  };
  EXPECT_EQ(deliver(4), 0);
  db->exec("PRAGMA max_page_count = " + std::to_string(full_disk_page_count(*db)));
  EXPECT_GT(deliver(40), 0);

  const std::string why = farm.store_write_error();
  EXPECT_NE(why.find("database or disk is full"), std::string::npos) << why;
  EXPECT_FALSE(farm.store_ready());
  EXPECT_NE(farm.store_unready_reason().find("the store cannot write: "), std::string::npos)
      << farm.store_unready_reason();

  // Reads answer: the job, the list, the workers, the totals, the tile map and the preview.
  EXPECT_EQ(farm.job(id).state, JobState::running);
  EXPECT_EQ(farm.jobs(10).size(), 1u);
  EXPECT_EQ(farm.workers().size(), 1u);
  EXPECT_EQ(farm.totals().jobs_by_state["running"], 1u);
  EXPECT_EQ(farm.tile_map(id).tiles.size(), 16u);
  EXPECT_FALSE(farm.image(id, "png").bytes.empty());

  // Still full at the next probe; space again: the probe after that commits.
  clock.advance(StoreHealth::kProbeIntervalMs);
  EXPECT_NE(farm.store_write_error(), "");
  db->exec("PRAGMA max_page_count = 1073741823");
  EXPECT_NE(farm.store_write_error(), "");  // not probed again yet
  clock.advance(StoreHealth::kProbeIntervalMs);
  EXPECT_EQ(farm.store_write_error(), "");
  EXPECT_TRUE(farm.store_ready());
  EXPECT_EQ(deliver(4), 0);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace tessera::server
