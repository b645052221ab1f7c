// Triangle meshes from Wavefront OBJ files, through tinyobjloader (docs/scenes.md, "Mesh files").
#pragma once

#include <glm/vec3.hpp>
#include <optional>
#include <string>
#include <vector>

#include "scene/scene.h"
#include "scene/file_reader.h"
#include "scene/mesh/triangle_mesh.h"

namespace tessera {

struct ObjOptions {
  bool read_materials = true;  ///< false: mtllib lines are not read, all faces form one group
  bool face_normals = false;   ///< true: vn normals are ignored
};

/// The faces of an OBJ file that share one material.
struct ObjGroup {
  std::string label;                 ///< the usemtl name; "" for faces without a known one
  std::optional<Material> material;  ///< from the MTL file, "<obj path>:<usemtl name>"
  glm::dvec3 emission{0};            ///< the material's Ke, radiance
  TriangleMesh mesh;                 ///< object space, triangles wound as the file's faces
};

struct ObjMesh {
  std::vector<ObjGroup> groups;        ///< one per material, in order of first use
  std::vector<std::string> mtl_files;  ///< bundle paths of the MTL files read
};

/// Parses OBJ text `bytes` read from bundle path `path`. MTL files named by mtllib are read
/// through `reader`, relative to the OBJ's folder. Faces with more than 3 vertices are split
/// (quads along their shorter diagonal, larger polygons as a fan), keeping their winding.
/// Per-vertex normals are kept for a group only when every corner of it has a vn (and not
/// `options.face_normals`) and all are non-zero; texture coordinates (vt) when every corner of
/// the group has one, as (u, 1 - v) (Mitsuba's orientation, v down the image). Throws
/// SceneError("<path>: ...") for a parse error, an unreadable MTL file, indices out of range,
/// non-finite coordinates or uvs, MTL values out of range, or more than kMaxMeshElements
/// vertices or faces.
ObjMesh load_obj(const std::string& path, const std::string& bytes, const FileReader& reader,
                 const ObjOptions& options);

}  // namespace tessera
