// Mitsuba's .vol grid files: a grid written the way Mitsuba 3 writes one reads back value for
// value in Mitsuba's order; every malformed header, a truncated file and non-finite values are
// refused naming the file and what is wrong.
#include "scene/volume_grid_file.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "scene/scene_error.h"

namespace tessera {
namespace {

template <typename T>
void append(std::string& out, T value) {
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  out.append(raw, sizeof(T));
}

/// A file as Mitsuba's VolumeGrid::write makes it.
std::string vol_bytes(int32_t nx, int32_t ny, int32_t nz, int32_t channels,
                      const std::vector<float>& values, int version = 3, int32_t encoding = 1) {
  std::string out = "VOL";
  out.push_back(char(version));
  append(out, encoding);
  append(out, nx);
  append(out, ny);
  append(out, nz);
  append(out, channels);
  for (float bound : {0.f, 0.f, 0.f, 1.f, 2.f, 3.f}) append(out, bound);
  for (float value : values) append(out, value);
  return out;
}

std::string grid_error(const std::string& bytes) {
  try {
    parse_volume_grid_file(bytes, "grids/a.vol");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(VolumeGridFile, ReadsValuesInMitsubasOrder) {
  // 2 x 3 x 2 voxels, 3 channels: value = 100 z + 10 y + x + channel / 10.
  std::vector<float> values;
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 2; ++x)
        for (int c = 0; c < 3; ++c) values.push_back(100.f * z + 10.f * y + x + c / 10.f);
  const VolumeGridFile grid = parse_volume_grid_file(vol_bytes(2, 3, 2, 3, values), "a.vol");
  EXPECT_EQ(grid.resolution, glm::u32vec3(2, 3, 2));
  EXPECT_EQ(grid.channels, 3u);
  EXPECT_EQ(grid.bbox_max, glm::vec3(1, 2, 3));
  ASSERT_EQ(grid.values.size(), values.size());
  EXPECT_EQ(grid.at(1, 2, 1, 2), 100.f + 20.f + 1.f + 0.2f);
  EXPECT_EQ(grid.at(0, 1, 0, 0), 10.f);
  EXPECT_EQ(grid.at(1, 0, 1, 1), 101.1f);
}

TEST(VolumeGridFile, NegativeValuesAndTrailingBytesAreKept) {
  // Signed distances are negative inside; Mitsuba reads only the values it needs.
  std::string bytes = vol_bytes(1, 1, 2, 1, {-0.5f, 0.25f});
  bytes += "extra";
  const VolumeGridFile grid = parse_volume_grid_file(bytes, "a.vol");
  EXPECT_EQ(grid.values, (std::vector<float>{-0.5f, 0.25f}));
}

TEST(VolumeGridFile, RefusesBadHeaders) {
  EXPECT_EQ(grid_error("VO"),
            "grids/a.vol: not a Mitsuba volume grid file (it must start with \"VOL\")");
  EXPECT_EQ(grid_error("PLY\3rest"),
            "grids/a.vol: not a Mitsuba volume grid file (it must start with \"VOL\")");
  EXPECT_EQ(grid_error(vol_bytes(1, 1, 1, 1, {0}, 2)),
            "grids/a.vol: volume grid file version 2; Mitsuba 3 and Tessera read version 3 only");
  EXPECT_EQ(grid_error(vol_bytes(1, 1, 1, 1, {0}).substr(0, 30)),
            "grids/a.vol: the file ends inside its 48-byte header (30 bytes)");
  EXPECT_EQ(grid_error(vol_bytes(1, 1, 1, 1, {0}, 3, 2)),
            "grids/a.vol: volume grid encoding 2; only 1 (float32) is read, as in Mitsuba 3");
  EXPECT_EQ(grid_error(vol_bytes(4, 0, 1, 1, {})),
            "grids/a.vol: the grid's y resolution is 0; it must be at least 1");
  EXPECT_EQ(grid_error(vol_bytes(1, 1, -3, 1, {})),
            "grids/a.vol: the grid's z resolution is -3; it must be at least 1");
  EXPECT_EQ(grid_error(vol_bytes(1, 1, 1, 0, {})),
            "grids/a.vol: the grid has 0 channels; it must have at least 1");
}

TEST(VolumeGridFile, RefusesGridsOverTheLimitBeforeReadingThem) {
  // 2^30 values claimed by a 48-byte file: refused by the count, nothing allocated.
  EXPECT_EQ(grid_error(vol_bytes(1024, 1024, 1024, 1, {})),
            "grids/a.vol: the grid holds more than 268435456 values (1024 x 1024 x 1024 x 1 "
            "channels), the most a grid file may hold");
  // The product of four int32 resolutions (2^124) does not wrap around to a small count.
  EXPECT_EQ(grid_error(vol_bytes(2147483647, 2147483647, 2147483647, 2147483647, {})),
            "grids/a.vol: the grid holds more than 268435456 values (2147483647 x 2147483647 x "
            "2147483647 x 2147483647 channels), the most a grid file may hold");
  EXPECT_EQ(grid_error(vol_bytes(65536, 65536, 65536, 1, {})),
            "grids/a.vol: the grid holds more than 268435456 values (65536 x 65536 x 65536 x 1 "
            "channels), the most a grid file may hold");
}

TEST(VolumeGridFile, RefusesTruncatedFiles) {
  EXPECT_EQ(grid_error(vol_bytes(2, 2, 2, 1, {1, 2, 3, 4, 5, 6, 7})),
            "grids/a.vol: the file ends after 7 of its 8 values (truncated)");
}

TEST(VolumeGridFile, RefusesNonFiniteValuesNamingTheVoxel) {
  std::vector<float> values(2 * 2 * 2 * 3, 1.f);
  values[((1 * 2 + 0) * 2 + 1) * 3 + 2] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(grid_error(vol_bytes(2, 2, 2, 3, values)),
            "grids/a.vol: voxel (1, 0, 1) channel 2 is NaN; grid values must be finite");
  values.assign(values.size(), 0.f);
  values[3] = -std::numeric_limits<float>::infinity();
  EXPECT_EQ(grid_error(vol_bytes(2, 2, 2, 3, values)),
            "grids/a.vol: voxel (1, 0, 0) channel 0 is infinite; grid values must be finite");
}

}  // namespace
}  // namespace tessera
