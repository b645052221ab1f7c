// Mitsuba's volume grid files (`.vol`, version 3), as its `gridvolume` volume and `sdfgrid` shape
// read them: a 48-byte little-endian header, then float32 values.
//
//   bytes  0-2   "VOL"
//   byte   3     version, 3
//   bytes  4-7   int32 encoding, 1 = float32 (the only one Mitsuba 3 reads)
//   bytes  8-19  int32 resolution x, y, z
//   bytes 20-23  int32 channels
//   bytes 24-47  float32 bounding box min x, y, z, max x, y, z (Mitsuba 3 keeps it but places a
//                grid by the plugin's to_world over [0, 1]^3, so Tessera keeps it for messages only)
//   then         x * y * z * channels float32 values, x fastest, a voxel's channels together:
//                value(x, y, z, c) = values[((z * ny + y) * nx + x) * channels + c]
//
// Hand-written: no Debian library reads this format (OpenVDB reads .vdb, not Mitsuba's .vol).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

namespace tessera {

/// The most values (x * y * z * channels) a grid file may hold: 2^28 (1 GiB of floats), the
/// same bound as an image's (image_check.h).
inline constexpr uint64_t kMaxVolumeGridValues = uint64_t(1) << 28;

/// The grid of one `.vol` file.
struct VolumeGridFile {
  glm::u32vec3 resolution{0, 0, 0};  ///< voxels along x, y, z; each >= 1
  uint32_t channels = 0;             ///< values per voxel, >= 1
  glm::vec3 bbox_min{0, 0, 0};       ///< the file's bounding box, as written
  glm::vec3 bbox_max{0, 0, 0};
  /// resolution.x * resolution.y * resolution.z * channels values, in the file's order (above).
  std::vector<float> values;

  float at(uint32_t x, uint32_t y, uint32_t z, uint32_t channel) const {
    return values[((size_t(z) * resolution.y + y) * resolution.x + x) * channels + channel];
  }
};

/// Reads the bytes of the grid file whose bundle path is `path` (for messages). Throws SceneError
/// "<path>: ..." when the magic, version or encoding is not Mitsuba's (version 3, float32), a
/// resolution or the channel count is below 1, the grid holds more than kMaxVolumeGridValues
/// values, the file ends before its last value, or a value is NaN or infinite (naming the first
/// such voxel and channel). Bytes after the last value are ignored, as Mitsuba ignores them.
VolumeGridFile parse_volume_grid_file(std::string_view bytes, const std::string& path);

}  // namespace tessera
