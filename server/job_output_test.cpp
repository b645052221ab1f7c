// JobOutput (server/job_output.h): a job's EXR and PNG written a row of tiles at a time, and its
// previews encoded so in memory, are the files that resolving the whole image first gives, byte
// for byte.
#include "job_output.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "accum/accumulation_codec.h"
#include "accum/film.h"
#include "job/tile_summary.h"

namespace tessera::server {
namespace {

namespace fs = std::filesystem;

/// An image file's bytes, with the EXR's `capDate` (the time OpenImageIO wrote it, to the
/// second) blanked, so that files written a second apart compare equal.
std::string file_bytes(const std::string& bytes) {
  std::string out = bytes;
  const std::string key("capDate\0string\0", 15);
  if (const size_t at = out.find(key); at != std::string::npos && at + key.size() + 4 + 19 <= out.size()) {
    out.replace(at + key.size() + 4, 19, 19, 'X');  // after the value's 4-byte size: "YYYY:MM:DD HH:MM:SS"
  }
  return out;
}
std::string file_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return file_bytes(std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()));
}

/// A 70 x 45 job in 32-px tiles (3 x 2, the last row and column cut short), 4-spp batches.
JobRecord job_of(StopRule rule) {
  JobRecord job;
  job.id = 7;
  job.scene_file = "scene.json";
  job.options.width = 70;
  job.options.height = 45;
  job.options.tile_size = 32;
  job.options.spp = 12;
  job.options.batch_spp = 4;
  job.options.rule = rule;
  if (rule == StopRule::noise) job.options.noise_target = 0.05;
  job.spp_merged = 4;
  return job;
}

/// Every tile of job_of's grid with a sum of `next_batch` batches of random samples (tile 4
/// has nothing merged): as positions for write, and with their bytes for resolve.
void tiles_of(const JobRecord& job, std::vector<TilePosition>* positions, std::vector<TileRecord>* records) {
  std::mt19937 random(11);
  std::uniform_real_distribution<float> value(0.0f, 2.0f);
  const uint32_t next_batches[] = {1, 3, 2, 1, 0, 3};
  uint32_t t = 0;
  for (int y0 = 0; y0 < job.options.height; y0 += 32) {
    for (int x0 = 0; x0 < job.options.width; x0 += 32) {
      const TileRect rect{x0, y0, std::min(x0 + 32, job.options.width), std::min(y0 + 32, job.options.height)};
      TileRecord record;
      record.tile = t;
      record.rect = rect;
      record.next_batch = next_batches[t];
      if (record.next_batch > 0) {
        Accumulation acc(rect);
        for (double& v : acc.rgb) v = value(random);
        for (uint32_t& n : acc.count) n = 4 * record.next_batch;
        acc.count[3] = 0;  // a pixel without samples stays black
        record.accumulation = encode_accumulation(acc);
      }
      positions->push_back({rect, record.next_batch});
      records->push_back(record);
      ++t;
    }
  }
}

/// The whole image first, every tile decoded into it (what the server wrote before it wrote a row
/// of tiles at a time), and the noise and time jobs' spp channel over the whole image.
RgbImage whole_image(const JobRecord& job, const std::vector<TileRecord>& tiles) {
  RgbImage image = resolve_image(job.options.width, job.options.height, {});
  for (const TileRecord& t : tiles) {
    if (!t.accumulation.empty()) resolve_into(image, decode_accumulation(t.accumulation));
  }
  return image;
}
std::vector<ExtraChannel> whole_extra_channels(const JobRecord& job, const std::vector<TileRecord>& tiles) {
  if (job.options.rule == StopRule::spp) return {};
  std::vector<TileRect> rects;
  std::vector<uint32_t> spp;
  for (const TileRecord& t : tiles) {
    rects.push_back(t.rect);
    spp.push_back(t.next_batch == 0 ? 0 : job.options.plan().batch_end(t.next_batch - 1));
  }
  return {{"spp", spp_channel(job.options.width, job.options.height, rects, spp)}};
}

class JobOutputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("tessera-job-output-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(JobOutputTest, FilesWrittenARowOfTilesAtATimeAreTheWholeImagesByteForByte) {
  for (const StopRule rule : {StopRule::spp, StopRule::noise}) {  // noise: the EXR's spp channel
    const JobRecord job = job_of(rule);
    std::vector<TilePosition> positions;
    std::vector<TileRecord> records;
    tiles_of(job, &positions, &records);
    int reads = 0;
    const JobOutput output(dir_ / "banded");
    const OutputFiles files = output.write(job, positions, [&](uint32_t tile) {
      ++reads;
      return records.at(tile).accumulation;
    });
    EXPECT_EQ(reads, 6);  // each tile once

    ImageWriteOptions options;
    options.metadata = JobOutput::provenance(job);
    options.extra_channels = whole_extra_channels(job, records);
    ASSERT_EQ(options.extra_channels.size(), rule == StopRule::spp ? 0u : 1u);
    fs::create_directories(dir_ / "whole");
    const RgbImage whole = whole_image(job, records);
    write_image(whole, dir_ / "whole" / "job.exr", options);
    write_image(whole, dir_ / "whole" / "job.png", options);
    EXPECT_EQ(file_bytes(files.exr), file_bytes(dir_ / "whole" / "job.exr"));
    EXPECT_EQ(file_bytes(files.png), file_bytes(dir_ / "whole" / "job.png"));
    EXPECT_GT(file_bytes(files.exr).size(), 1000u);
    EXPECT_NE(file_bytes(files.exr).find(std::string(19, 'X')), std::string::npos) << "capDate not blanked";
    // A preview (the job's image before its files exist) is the same file, encoded in memory.
    const auto read = [&](uint32_t tile) { return records.at(tile).accumulation; };
    EXPECT_EQ(file_bytes(JobOutput::encode(job, positions, read, "exr")), file_bytes(files.exr));
    EXPECT_EQ(file_bytes(JobOutput::encode(job, positions, read, "png")), file_bytes(files.png));
  }
}

TEST_F(JobOutputTest, TilesThatLeaveRowsUncoveredAreAnErrorAndNoFileIsLeft) {
  const JobRecord job = job_of(StopRule::spp);
  std::vector<TilePosition> positions;
  std::vector<TileRecord> records;
  tiles_of(job, &positions, &records);
  positions.resize(3);  // the second row of tiles is missing
  try {
    JobOutput(dir_).write(job, positions, [&](uint32_t tile) { return records.at(tile).accumulation; });
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("rows 32 to 44 uncovered"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_empty(dir_));  // neither file, nor a temporary one
}

// A worker's renderer build has commas of its own (worker/render/renderer_build.h): the
// provenance separates builds by "; ", so two builds read as two (docs/design.md).
TEST(JobOutputProvenance, NamesEveryRendererBuildApartAndTheIsasCommaSeparated) {
  JobRecord job;
  job.versions = {"0.1.0 (commit 0123456789ab, GNU 12.2.0, Embree 3.13.5, glibc 2.36)",
                  "0.1.0 (commit ba9876543210, Clang 14.0.6, Embree 3.13.5, glibc 2.36)"};
  job.isas = {"avx2", "avx512"};
  const auto m = JobOutput::provenance(job);
  EXPECT_EQ(m.at("tessera:renderer_version"),
            "0.1.0 (commit 0123456789ab, GNU 12.2.0, Embree 3.13.5, glibc 2.36); "
            "0.1.0 (commit ba9876543210, Clang 14.0.6, Embree 3.13.5, glibc 2.36)");
  EXPECT_EQ(m.at("tessera:isa"), "avx2,avx512");
  job.versions.resize(1);
  EXPECT_EQ(JobOutput::provenance(job).at("tessera:renderer_version"), job.versions[0]);
}

}  // namespace
}  // namespace tessera::server
