// The render-ready form of one scene shape: what an Embree geometry id maps back to.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "render/texture/mesh_attribute_table.h"

namespace tessera {

class SdfGrid;

struct Geometry {
  /// instance: a placed shape group (Embree instance); its shapes are in TraceableScene's group
  /// tables and `to_world` maps their space to the world.
  /// curves: Embree round curves (worker/render/geometry/curve.h).
  /// sdfgrid: user geometry over the grid's surface bricks (worker/render/geometry/sdf_grid.h).
  enum class Kind { triangles, sphere, instance, curves, sdfgrid };
  Kind kind = Kind::triangles;

  // Kind::triangles (float copies of the world-space data Embree traces)
  std::vector<glm::vec3> positions;
  std::vector<glm::u32vec3> indices;
  std::vector<glm::vec3> normals;  ///< per vertex; empty = flat shading
  std::vector<glm::vec2> uvs;      ///< per vertex texture coordinates; empty = none ((0, 0))
  /// Per triangle, precomputed: unit geometric normal (counter-clockwise front) and the error
  /// bound of points on it (ray_offset.h, triangle_point_error).
  std::vector<glm::vec3> face_normals;
  std::vector<float> point_errors;
  /// The shape's mesh attributes that the scene's mesh_attribute textures read; empty = none.
  MeshAttributeTable attributes;

  // Kind::sphere, in double: the user-geometry intersector solves in double precision.
  glm::dvec3 center{0.0};
  double radius = 1.0;
  bool inward = false;  ///< front faces the centre
  glm::mat3 frame{1.0f};  ///< rotation of the sphere's own frame: its uv are measured there

  // Kind::instance
  uint32_t group = 0;
  glm::mat4 to_world{1.0f};
  glm::mat4 to_object{1.0f};        ///< inverse of to_world
  glm::mat3 normal_to_world{1.0f};  ///< inverse transpose of to_world's linear part
  float transform_error = 0;        ///< relative error bound of points mapped by to_world

  // Kind::curves (float copies of what Embree traces): (x, y, z, radius) per control point,
  // the first control point of each segment, and whether they are cubic B-splines.
  std::vector<glm::vec4> control_points;
  std::vector<uint32_t> segments;
  bool bspline = false;

  // Kind::sdfgrid: the grid and its intersector, in the shape's space.
  std::shared_ptr<const SdfGrid> sdf;

  uint32_t material = 0;
  int32_t emitter = -1;          ///< area emitter index in TraceableScene::lights(), -1 if none
  glm::vec3 emission{0.0f};      ///< radiance of the front (and back when two-sided)
  int32_t emission_texture = -1; ///< radiance = emission * texture(uv) when >= 0
  bool two_sided_emission = false;
};

}  // namespace tessera
