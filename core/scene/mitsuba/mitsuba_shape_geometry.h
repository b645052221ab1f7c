// The object-space geometry of Mitsuba's built-in shapes (docs/mitsuba.md, "Shapes"), with
// Mitsuba's texture coordinates.
#pragma once

#include <glm/vec2.hpp>
#include <vector>

#include "scene/mesh/triangle_mesh.h"

namespace tessera {

/// Triangles of the disk's fan: Tessera renders triangles and exact spheres only, so Mitsuba's
/// analytic disk is tessellated; its area is 256/(2 pi) sin(2 pi/256) = 99.99 % of the disk's.
inline constexpr int kMitsubaDiskSegments = 256;

/// A built-in shape as triangles with one (u, v) per vertex.
struct MitsubaBuiltinMesh {
  TriangleMesh mesh;
  std::vector<glm::dvec2> uvs;
};

/// Mitsuba's `rectangle`: the square (-1, -1, 0)..(1, 1, 0), front +z; two triangles;
/// (u, v) = ((x + 1) / 2, (y + 1) / 2), as Mitsuba's rectangle.
MitsubaBuiltinMesh mitsuba_rectangle();

/// Mitsuba's `cube`: [-1, 1]^3, fronts facing out, flat; as Mitsuba builds it: 4 vertices per
/// face (24 in all) with (u, v) = (0, 1), (1, 1), (1, 0), (0, 0) and triangles {4s, 4s+1, 4s+2},
/// {4s+3, 4s, 4s+2}.
MitsubaBuiltinMesh mitsuba_cube();

/// Mitsuba's `disk`: the unit disk in the plane z = 0, front +z, as a fan of
/// kMitsubaDiskSegments triangles; (u, v) = (r, phi / 2 pi) as Mitsuba's disk, exact at the
/// vertices (each triangle has its own centre vertex at v = its middle angle, and the rim is
/// closed by a vertex at v = 1).
MitsubaBuiltinMesh mitsuba_disk();

}  // namespace tessera
