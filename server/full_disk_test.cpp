// A full output disk: the job that completes while the disk is full stays done with
// its merged image in the store; `get` answers the final image and writes the files again once
// space is back, and so does the next server start. ENOSPC comes through the output opener's
// seam (CoordinatorConfig::output_opener).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "accum/accumulation_codec.h"
#include "coordinator.h"
#include "fake_clock.h"
#include "store_fixture.h"

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
    const JobRecord job = farm.job(id);
    EXPECT_EQ(job.state, JobState::done);
    EXPECT_EQ(job.error, "");
    EXPECT_FALSE(std::filesystem::exists(job.output_exr));
    // No half-written or temporary file either.
    EXPECT_TRUE(!std::filesystem::exists(dir / "outputs") || std::filesystem::is_empty(dir / "outputs"));

    // Still full: `get` answers the final image from the store.
    JobImage image = farm.image(id, "exr");
    EXPECT_TRUE(image.final);
    EXPECT_EQ(image.spp, 4u);
    EXPECT_FALSE(image.bytes.empty());
    EXPECT_FALSE(std::filesystem::exists(job.output_exr));

    // Space is back: the next `get` writes both files.
    disk.full = false;
    image = farm.image(id, "png");
    EXPECT_TRUE(image.final);
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

}  // namespace
}  // namespace tessera::server
