#include "scene/mesh/mesh_file.h"

#include <algorithm>
#include <cctype>

#include "scene/mesh/obj_loader.h"
#include "scene/mesh/ply_loader.h"
#include "scene/mesh/serialized_loader.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

std::string lowercase_extension(const std::string& path) {
  size_t slash = path.rfind('/');
  size_t dot = path.rfind('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string extension = path.substr(dot);
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return extension;
}

std::vector<MeshPart> load_obj_parts(const std::string& path, const std::string& bytes,
                                     const FileReader& reader, const MeshFileOptions& options,
                                     std::vector<std::string>& files_read) {
  ObjOptions obj_options;
  obj_options.read_materials = options.use_file_materials;
  obj_options.face_normals = options.face_normals;
  ObjMesh obj = load_obj(path, bytes, reader, obj_options);
  files_read.insert(files_read.end(), obj.mtl_files.begin(), obj.mtl_files.end());
  std::vector<MeshPart> parts;
  for (ObjGroup& group : obj.groups) {
    MeshPart part;
    part.label = group.label;
    part.material = std::move(group.material);
    part.emission = group.emission;
    part.mesh = std::move(group.mesh);
    parts.push_back(std::move(part));
  }
  return parts;
}

}  // namespace

std::vector<MeshPart> load_mesh_file(const std::string& path, const FileReader& reader,
                                     const MeshFileOptions& options,
                                     std::vector<std::string>& files_read) {
  std::string extension = lowercase_extension(path);
  if (extension != ".obj" && extension != ".ply" && extension != ".serialized") {
    throw SceneError(path +
                     ": unsupported mesh format (expected a .obj, .ply or .serialized file)");
  }
  std::string bytes = reader(path);
  files_read.push_back(path);
  if (extension == ".obj") return load_obj_parts(path, bytes, reader, options, files_read);
  MeshPart part;
  if (extension == ".serialized") {
    part.mesh =
        load_serialized_mesh(bytes, path, options.shape_index, !options.face_normals).mesh;
  } else {
    PlyMesh ply = load_ply(bytes, path, !options.face_normals);
    part.mesh = std::move(ply.mesh);
    part.dropped_faces = ply.dropped_faces;
  }
  std::vector<MeshPart> parts;
  parts.push_back(std::move(part));
  return parts;
}

}  // namespace tessera
