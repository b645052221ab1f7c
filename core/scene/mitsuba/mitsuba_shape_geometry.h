// The object-space geometry of Mitsuba's built-in shapes (docs/mitsuba.md, "Shapes").
#pragma once

#include "scene/mesh/triangle_mesh.h"

namespace tessera {

/// Triangles of the disk's fan: Tessera renders triangles and exact spheres only, so Mitsuba's
/// analytic disk is tessellated; its area is 256/(2 pi) sin(2 pi/256) = 99.99 % of the disk's.
inline constexpr int kMitsubaDiskSegments = 256;

/// Mitsuba's `rectangle`: the square (-1, -1, 0)..(1, 1, 0), front +z; two triangles.
TriangleMesh mitsuba_rectangle();

/// Mitsuba's `cube`: [-1, 1]^3, fronts facing out; 8 vertices, 12 triangles (flat, as Mitsuba's
/// cube with its per-face normals is).
TriangleMesh mitsuba_cube();

/// Mitsuba's `disk`: the unit disk in the plane z = 0, front +z, as a fan of
/// kMitsubaDiskSegments triangles around its centre.
TriangleMesh mitsuba_disk();

}  // namespace tessera
