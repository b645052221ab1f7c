// Test helper: the bytes of a Mitsuba `.vol` grid file (core/scene/volume_grid_file.h),
// for the volume texture's tests in core/ and worker/.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace tessera::testing {

/// A version-3 float32 grid of resolution `res` and `channels`, values in file order (x
/// fastest, a voxel's channels together), bounding box [bbox_min, bbox_max].
inline std::string volume_grid_bytes(glm::ivec3 res, int channels, const std::vector<float>& values,
                                     glm::vec3 bbox_min = glm::vec3(0.0f),
                                     glm::vec3 bbox_max = glm::vec3(1.0f)) {
  std::string out = "VOL";
  out.push_back(char(3));
  auto put = [&out](const void* p, size_t n) { out.append(static_cast<const char*>(p), n); };
  const int32_t header[5] = {1, res.x, res.y, res.z, channels};
  put(header, sizeof header);  // little-endian hosts only, as the tests run
  const float bbox[6] = {bbox_min.x, bbox_min.y, bbox_min.z, bbox_max.x, bbox_max.y, bbox_max.z};
  put(bbox, sizeof bbox);
  put(values.data(), values.size() * sizeof(float));
  return out;
}

}  // namespace tessera::testing
