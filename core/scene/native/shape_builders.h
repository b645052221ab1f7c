// Object-space geometry of the built-in shape types (docs/scenes.md, "`shapes`").
//
// Each builder reads its own keys of a shape object and throws SceneError naming the JSON path
// of what is wrong. Triangles are counter-clockwise seen from the front.
#pragma once

#include <glm/vec3.hpp>

#include "scene/native/json_value.h"
#include "scene/mesh/triangle_mesh.h"

namespace tessera {

/// "quad": "vertices", 4 points counter-clockwise seen from the front, planar (within 1e-5 of
/// the quad's size), convex and non-degenerate. Triangles (0,1,2), (0,2,3).
TriangleMesh build_quad(const JsonValue& shape);

/// "triangles": "vertices" (points), "indices" ([i,j,k] in range), optional "normals" (one
/// non-zero vector per vertex). Degenerate triangles are checked later, in world space.
TriangleMesh build_triangles(const JsonValue& shape);

/// "box": "min" and "max" corners (default -1 and 1, min < max on every axis). 12 triangles,
/// fronts facing out of the box.
TriangleMesh build_box(const JsonValue& shape);

/// "tetrahedron": "vertices", 4 points not in one plane, in any order. 4 triangles, fronts
/// facing out of the tetrahedron.
TriangleMesh build_tetrahedron(const JsonValue& shape);

struct SphereGeometry {
  glm::dvec3 center{0, 0, 0};
  double radius = 1;
  glm::dmat3 frame{1.0};  ///< Shape::frame
};

/// "sphere": "center" (default origin), "radius" (> 0, default 1), "frame" (3 x 3 rows of an
/// orthogonal matrix, default identity).
SphereGeometry build_sphere(const JsonValue& shape);

}  // namespace tessera
