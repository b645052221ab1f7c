// Mesh files a "mesh" shape names: OBJ (with MTL), PLY and Mitsuba's serialized, chosen by
// extension. mesh/ reads files into the model (core/scene/) and includes nothing above it
// (the layers: scene.h).
#pragma once

#include <cstddef>
#include <glm/vec3.hpp>
#include <optional>
#include <string>
#include <vector>

#include "scene/scene.h"
#include "scene/file_reader.h"
#include "scene/mesh/triangle_mesh.h"

namespace tessera {

/// The triangles of a mesh file that share one material.
struct MeshPart {
  std::string label;                 ///< the MTL material name; "" when the file has none
  std::optional<Material> material;  ///< from the file's MTL (OBJ only)
  glm::dvec3 emission{0};            ///< the MTL material's Ke
  TriangleMesh mesh;                 ///< object space
  size_t dropped_faces = 0;          ///< faces with fewer than 3 vertices, dropped while reading
};

struct MeshFileOptions {
  bool use_file_materials = true;  ///< read the OBJ's MTL files and group faces by material
  bool face_normals = false;       ///< ignore the file's normals
  int shape_index = 0;             ///< .serialized only: which shape of the file, >= 0
};

/// Loads the mesh file at bundle path `path` (already checked with check_bundle_path) through
/// `reader`: ".obj" (case-insensitive) with tinyobjloader, ".ply" with load_ply, ".serialized"
/// with load_serialized_mesh (shape `options.shape_index`). Appends every
/// file read (the mesh, then its MTL files) to `files_read`. Returns one part per material (a
/// PLY or serialized file, or an OBJ read without its materials, gives one part). Throws
/// SceneError("<path>: ...").
std::vector<MeshPart> load_mesh_file(const std::string& path, const FileReader& reader,
                                     const MeshFileOptions& options,
                                     std::vector<std::string>& files_read);

}  // namespace tessera
