// Helpers shared by the scene library's tests (core/scene/**/*_test.cpp), over the scene model
// alone: every folder's tests may use them.
#pragma once

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <map>
#include <string>

#include "scene/file_reader.h"
#include "scene/scene.h"
#include "scene/scene_error.h"

namespace tessera::testing {

/// A FileReader over in-memory files, failing as folder_reader does for missing ones.
inline FileReader memory_reader(std::map<std::string, std::string> files) {
  return [files = std::move(files)](const std::string& path) -> std::string {
    auto it = files.find(path);
    if (it == files.end()) throw SceneError(path + ": no such file in the scene's folder");
    return it->second;
  };
}

/// The geometric normal (from the winding) of triangle `t`, unit length.
inline glm::dvec3 face_normal(const Shape& shape, size_t t) {
  const glm::u32vec3& i = shape.indices[t];
  const std::vector<glm::dvec3>& p = shape.positions;
  return glm::normalize(glm::cross(p[i.y] - p[i.x], p[i.z] - p[i.x]));
}

inline glm::dvec3 face_center(const Shape& shape, size_t t) {
  const glm::u32vec3& i = shape.indices[t];
  return (shape.positions[i.x] + shape.positions[i.y] + shape.positions[i.z]) / 3.0;
}

inline double shape_area(const Shape& shape) {
  double area = 0;
  for (const glm::u32vec3& i : shape.indices) {
    const std::vector<glm::dvec3>& p = shape.positions;
    area += 0.5 * glm::length(glm::cross(p[i.y] - p[i.x], p[i.z] - p[i.x]));
  }
  return area;
}

inline void expect_near(const glm::dvec3& a, const glm::dvec3& b, double tolerance = 1e-9) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

}  // namespace tessera::testing
