// The object-space geometry of Mitsuba's built-in shapes (docs/mitsuba.md, "Shapes"), with
// Mitsuba's texture coordinates.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
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

/// Mitsuba's `cylinder` in its own space: the open tube of radius 1 around the z axis from
/// z = 0 to z = 1, fronts outward, tessellated like the disk into kMitsubaDiskSegments quads
/// (two triangles each) with radial vertex normals (smooth, as Mitsuba's analytic normal);
/// (u, v) = (phi / 2 pi, z) as Mitsuba's, exact at the vertices (the seam has its own column
/// of vertices at u = 1).
MitsubaBuiltinMesh mitsuba_cylinder();

/// Mitsuba's placement of a cylinder from p0 to p1 of `radius` (before the shape's to_world):
/// translate(p0) * to_frame(Frame(d / |d|)) * scale(radius, radius, |d|), d = p1 - p0, with
/// Mitsuba's coordinate_system for the frame (Duff et al. 2017). Not finite when p0 = p1.
glm::dmat4 mitsuba_cylinder_placement(const glm::dvec3& p0, const glm::dvec3& p1, double radius);

/// Mitsuba's `disk`: the unit disk in the plane z = 0, front +z, as a fan of
/// kMitsubaDiskSegments triangles; (u, v) = (r, phi / 2 pi) as Mitsuba's disk, exact at the
/// vertices (each triangle has its own centre vertex at v = its middle angle, and the rim is
/// closed by a vertex at v = 1).
MitsubaBuiltinMesh mitsuba_disk();

}  // namespace tessera
