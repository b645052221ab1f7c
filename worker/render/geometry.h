// The render-ready form of one scene shape: what an Embree geometry id maps back to.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace tessera {

struct Geometry {
  enum class Kind { triangles, sphere };
  Kind kind = Kind::triangles;

  // Kind::triangles (float copies of the world-space data Embree traces)
  std::vector<glm::vec3> positions;
  std::vector<glm::u32vec3> indices;
  std::vector<glm::vec3> normals;  ///< per vertex; empty = flat shading
  /// Per triangle, precomputed: unit geometric normal (counter-clockwise front) and the error
  /// bound of points on it (ray_offset.h, triangle_point_error).
  std::vector<glm::vec3> face_normals;
  std::vector<float> point_errors;

  // Kind::sphere, in double: the user-geometry intersector solves in double precision.
  glm::dvec3 center{0.0};
  double radius = 1.0;
  bool inward = false;  ///< front faces the centre

  uint32_t material = 0;
  int32_t emitter = -1;          ///< index into TraceableScene::emitters(), -1 if none
  glm::vec3 emission{0.0f};      ///< radiance of the front (and back when two-sided)
  bool two_sided_emission = false;
};

}  // namespace tessera
