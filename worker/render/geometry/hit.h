// What a closest-hit query found: the point, its normals, texture coordinates and the shape.
#pragma once

#include <cstdint>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "render/geometry/geometry.h"
#include "render/math/ray_offset.h"

namespace tessera {

/// What a closest-hit query found.
struct Hit {
  SurfacePoint sp;        ///< point, error bound, unit geometric normal (the shape's front)
  glm::vec3 ns;           ///< unit shading normal, on the same side as sp.ng
  /// Texture coordinates and the surface's partial derivatives along them (world space), as
  /// Mitsuba defines them: interpolated vertex uvs on meshes (barycentrics (b1, b2) without
  /// uvs, then dpdu, dpdv are the triangle's edges), (phi / 2 pi, theta / pi) on spheres in
  /// their own frame, (angle around the tube / 2 pi, v along all segments) on curves
  /// (geometry/curve.h); (0, 0) with zero tangents on SDF grids, as in Mitsuba. dpdu may be
  /// zero at a sphere's poles.
  glm::vec2 uv{0.0f};
  glm::vec3 dpdu{0.0f}, dpdv{0.0f};
  const Geometry* geometry = nullptr;  ///< the shape hit (a group's shape for instances)
  uint32_t primitive = 0;
  glm::vec2 barycentric{0.0f};  ///< triangles: Embree's (b1, b2) of the hit (mesh attributes)
  /// Embree's ids of the hit: top-level geometry (the instance for a group's shape) and, for
  /// instances, the shape inside the group; they key per-hit decisions such as masks.
  uint32_t geometry_id = 0;
};

}  // namespace tessera
