// The grid files shared by the sdfgrid shape's tests (native/sdfgrid_shape_test.cpp,
// mitsuba/mitsuba_sdfgrid_test.cpp).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace tessera::testing {

/// A Mitsuba .vol file (version 3, float32) of the given grid.
inline std::string vol_file(uint32_t nx, uint32_t ny, uint32_t nz, uint32_t channels, const std::vector<float>& values) {
  std::string out = "VOL";
  out.push_back(char(3));
  auto put = [&](const void* p, size_t n) { out.append(static_cast<const char*>(p), n); };
  const int32_t header[5] = {1, int32_t(nx), int32_t(ny), int32_t(nz), int32_t(channels)};
  put(header, sizeof(header));
  const float box[6] = {0, 0, 0, 1, 1, 1};
  put(box, sizeof(box));
  put(values.data(), values.size() * sizeof(float));
  return out;
}

/// Distance to a sphere of radius 0.3 around (0.5, 0.5, 0.5), sampled on n^3 points of [0, 1]^3.
inline std::vector<float> sphere_values(uint32_t n) {
  std::vector<float> v;
  for (uint32_t z = 0; z < n; ++z) {
    for (uint32_t y = 0; y < n; ++y) {
      for (uint32_t x = 0; x < n; ++x) {
        const glm::dvec3 p = glm::dvec3(x, y, z) / double(n - 1);
        v.push_back(float(glm::length(p - glm::dvec3(0.5)) - 0.3));
      }
    }
  }
  return v;
}

/// The grid files of the sdfgrid tests: a ball, and three that cannot be an SDF grid.
inline const std::map<std::string, std::string> kSdfGridFiles = {
    {"ball.vol", vol_file(5, 5, 5, 1, sphere_values(5))},
    {"two.vol", vol_file(2, 2, 2, 2, std::vector<float>(16, -1.0f))},
    {"flat.vol", vol_file(1, 4, 4, 1, std::vector<float>(16, -1.0f))},
    {"solid.vol", vol_file(3, 3, 3, 1, std::vector<float>(27, 0.5f))},
};

}  // namespace tessera::testing
