#include "scene/volume_grid_file.h"

#include <bit>
#include <cmath>
#include <cstring>

#include "scene/scene_error.h"

namespace tessera {
namespace {

static_assert(std::endian::native == std::endian::little,
              "the .vol reader copies little-endian values as they are");

constexpr size_t kHeaderBytes = 48;

int32_t read_int32(std::string_view bytes, size_t offset) {
  int32_t value;
  std::memcpy(&value, bytes.data() + offset, sizeof value);
  return value;
}

float read_float(std::string_view bytes, size_t offset) {
  float value;
  std::memcpy(&value, bytes.data() + offset, sizeof value);
  return value;
}

}  // namespace

VolumeGridFile parse_volume_grid_file(std::string_view bytes, const std::string& path) {
  if (bytes.size() < 4 || bytes.substr(0, 3) != "VOL") {
    throw SceneError(path + ": not a Mitsuba volume grid file (it must start with \"VOL\")");
  }
  const auto version = static_cast<unsigned char>(bytes[3]);
  if (version != 3) {
    throw SceneError(path + ": volume grid file version " + std::to_string(version) +
                     "; Mitsuba 3 and Tessera read version 3 only");
  }
  if (bytes.size() < kHeaderBytes) {
    throw SceneError(path + ": the file ends inside its 48-byte header (" +
                     std::to_string(bytes.size()) + " bytes)");
  }
  const int32_t encoding = read_int32(bytes, 4);
  if (encoding != 1) {
    throw SceneError(path + ": volume grid encoding " + std::to_string(encoding) +
                     "; only 1 (float32) is read, as in Mitsuba 3");
  }
  const int32_t size[3] = {read_int32(bytes, 8), read_int32(bytes, 12), read_int32(bytes, 16)};
  const int32_t channels = read_int32(bytes, 20);
  static const char* kAxis[3] = {"x", "y", "z"};
  for (int axis = 0; axis < 3; ++axis) {
    if (size[axis] < 1) {
      throw SceneError(path + ": the grid's " + kAxis[axis] + " resolution is " +
                       std::to_string(size[axis]) + "; it must be at least 1");
    }
  }
  if (channels < 1) {
    throw SceneError(path + ": the grid has " + std::to_string(channels) +
                     " channels; it must have at least 1");
  }
  // Multiplied factor by factor, stopping above the limit: each factor is below 2^31, so a
  // product at most 2^28 times one of them never wraps.
  uint64_t count = 1;
  for (int32_t factor : {size[0], size[1], size[2], channels}) {
    count *= uint64_t(factor);
    if (count > kMaxVolumeGridValues) {
      throw SceneError(path + ": the grid holds more than " +
                       std::to_string(kMaxVolumeGridValues) + " values (" +
                       std::to_string(size[0]) + " x " + std::to_string(size[1]) + " x " +
                       std::to_string(size[2]) + " x " + std::to_string(channels) +
                       " channels), the most a grid file may hold");
    }
  }
  if (bytes.size() - kHeaderBytes < count * sizeof(float)) {
    throw SceneError(path + ": the file ends after " +
                     std::to_string((bytes.size() - kHeaderBytes) / sizeof(float)) + " of its " +
                     std::to_string(count) + " values (truncated)");
  }

  VolumeGridFile grid;
  grid.resolution = glm::u32vec3(uint32_t(size[0]), uint32_t(size[1]), uint32_t(size[2]));
  grid.channels = uint32_t(channels);
  grid.bbox_min = glm::vec3(read_float(bytes, 24), read_float(bytes, 28), read_float(bytes, 32));
  grid.bbox_max = glm::vec3(read_float(bytes, 36), read_float(bytes, 40), read_float(bytes, 44));
  grid.values.resize(count);
  std::memcpy(grid.values.data(), bytes.data() + kHeaderBytes, count * sizeof(float));
  for (uint64_t i = 0; i < count; ++i) {
    if (std::isfinite(grid.values[i])) continue;
    const uint64_t voxel = i / grid.channels;
    const uint64_t x = voxel % grid.resolution.x;
    const uint64_t y = voxel / grid.resolution.x % grid.resolution.y;
    const uint64_t z = voxel / grid.resolution.x / grid.resolution.y;
    throw SceneError(path + ": voxel (" + std::to_string(x) + ", " + std::to_string(y) + ", " +
                     std::to_string(z) + ") channel " + std::to_string(i % grid.channels) +
                     " is " + (std::isnan(grid.values[i]) ? "NaN" : "infinite") +
                     "; grid values must be finite");
  }
  return grid;
}

}  // namespace tessera
