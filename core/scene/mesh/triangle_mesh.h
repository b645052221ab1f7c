// Triangle soup in one space, and the operations the parser applies to it.
#pragma once

#include <cstddef>
#include <glm/gtc/type_precision.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <optional>
#include <vector>

#include "scene/mesh_attribute.h"
#include "scene/transform.h"

namespace tessera {

/// Positions, optional per-vertex shading normals and texture coordinates, and triangles
/// counter-clockwise seen from the front. Shape::positions/normals/uvs/indices in the making.
struct TriangleMesh {
  std::vector<glm::dvec3> positions;
  std::vector<glm::dvec3> normals;  ///< one per position, or empty
  std::vector<glm::dvec2> uvs;      ///< one per position, or empty (Shape::uvs)
  std::vector<glm::u32vec3> indices;
  /// Mitsuba's mesh attributes (PLY files): "vertex_*" one row per position, "face_*" one per
  /// triangle (kept in step with `indices` by drop_degenerate_triangles).
  std::vector<MeshAttribute> attributes;
};

/// Maps the mesh to world space: positions by `transform`, normals by its inverse transpose,
/// and, when the transform mirrors, every triangle's winding reversed so that the front stays
/// the side the (transformed) normals point to. Normals must be non-zero.
void transform_mesh(TriangleMesh& mesh, const Transform& transform);

/// Turns the front to the other side: reverses the winding and negates the normals.
void flip_mesh(TriangleMesh& mesh);

/// Area of triangle (a, b, c).
double triangle_area(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c);

/// True when (a, b, c) has zero area up to rounding: coincident points, or collinear within a
/// relative tolerance (sine of the angle at a below 1e-12).
bool is_degenerate_triangle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c);

/// Sum of the triangles' areas.
double mesh_area(const TriangleMesh& mesh);

/// The index of the first degenerate triangle, or nullopt when there is none.
std::optional<size_t> first_degenerate_triangle(const TriangleMesh& mesh);

/// Removes degenerate triangles (vertices stay) and their rows of face attributes; returns how
/// many were removed.
size_t drop_degenerate_triangles(TriangleMesh& mesh);

/// True when every position is finite.
bool positions_finite(const TriangleMesh& mesh);

/// True when every normal is finite and non-zero.
bool normals_usable(const TriangleMesh& mesh);

}  // namespace tessera
