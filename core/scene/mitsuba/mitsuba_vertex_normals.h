// Shading normals of Mitsuba meshes: those Mitsuba computes for mesh files without any, and the
// form in which the importer stores normals.
#pragma once

#include <glm/vec3.hpp>

#include "scene/mesh/triangle_mesh.h"

namespace tessera {

/// Sets `mesh.normals` as Mitsuba's Mesh::recompute_vertex_normals does for OBJ and PLY files
/// without normals (unless face_normals): each triangle's unit normal, weighted by its angle at
/// the vertex (Thuermer and Wuethrich 1998), summed per vertex and normalised; a vertex whose
/// sum is zero gets (1, 0, 0), as in Mitsuba. Vertices are shared as the file shares them.
void compute_mitsuba_vertex_normals(TriangleMesh& mesh);

/// A unit vector within a few ulps of unit vector `n` that glm::normalize leaves unchanged.
///
/// Why: the native parser renormalises every normal it reads, and normalising is not
/// idempotent in floating point (about a third of unit vectors move by an ulp). Normals stored
/// in this form survive `tessera-worker convert` and parse_scene bit for bit, so an imported
/// scene and its converted JSON render identical pixels. Found by nudging the largest
/// component (in practice at most 5 ulps); returns `n` itself when it is already stable, or
/// when no stable neighbour is found within 64 ulps.
glm::dvec3 stable_unit_vector(const glm::dvec3& n);

}  // namespace tessera
