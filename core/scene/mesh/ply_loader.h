// Triangle meshes from PLY files (docs/scenes.md, "Mesh files"). See ply_header.h for why Tessera
// reads PLY itself.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "scene/mesh/triangle_mesh.h"

namespace tessera {

struct PlyMesh {
  TriangleMesh mesh;         ///< object space; polygons fan-triangulated, winding kept
  size_t dropped_faces = 0;  ///< faces with fewer than 3 vertices
};

/// Reads PLY `bytes` (ascii, binary_little_endian or binary_big_endian). Element "vertex" needs
/// scalar properties x, y, z (any numeric type, any order; other properties are skipped) and may
/// have nx, ny, nz (read when `read_normals` and all three are there; dropped when one is zero or
/// not finite), and texture coordinates u, v (or s, t, or texture_u, texture_v, the first pair
/// present; stored as they are, as Mitsuba does). Element "face" needs a list "vertex_indices" (or
/// "vertex_index") of integers. Other scalar properties of the two elements become mesh
/// attributes under Mitsuba's names (ply_attributes.h; a polygon's face row goes to each triangle
/// of its fan). Other elements are skipped. Throws SceneError("<name>: ...") for
/// bad headers, truncated data, non-finite coordinates, indices out of range, and for more than
/// kMaxMeshElements vertices, faces or triangles (refused before allocating).
PlyMesh load_ply(std::string_view bytes, const std::string& name, bool read_normals);

}  // namespace tessera
