#include "scene/mesh/obj_material_reader.h"

#include <sstream>

#include "scene/bundle_path.h"
#include "scene/scene_error.h"

namespace tessera {

ObjMaterialReader::ObjMaterialReader(std::string obj_path, const FileReader& reader)
    : obj_path_(std::move(obj_path)), reader_(reader) {}

bool ObjMaterialReader::operator()(const std::string& mtl_name,
                                   std::vector<tinyobj::material_t>* materials,
                                   std::map<std::string, int>* material_map, std::string* warning,
                                   std::string* error) {
  std::string path;
  std::string bytes;
  try {
    std::string relative = check_bundle_path(mtl_name, obj_path_ + ": mtllib");
    size_t slash = obj_path_.rfind('/');
    path = slash == std::string::npos ? relative : obj_path_.substr(0, slash + 1) + relative;
  } catch (const SceneError& e) {
    if (!error_) error_ = e.what();
    return false;
  }
  try {
    bytes = reader_(path);
  } catch (const SceneError& e) {
    if (!error_) error_ = obj_path_ + ": mtllib: " + e.what();
    return false;
  }
  std::istringstream stream(bytes);
  tinyobj::LoadMtl(material_map, materials, &stream, warning, error);
  files_.push_back(path);
  return true;
}

}  // namespace tessera
