// Feeding tinyobjloader the MTL files of an OBJ from the scene bundle.
//
// Internal to tessera_core (see mtl_material.h about TINYOBJLOADER_USE_DOUBLE).
#pragma once

#include <tiny_obj_loader.h>

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "scene/file_reader.h"

namespace tessera {

/// Reads the MTL files an OBJ names ("mtllib") through the scene's FileReader, relative to the
/// OBJ's folder and under the same path rules as every bundle path (check_bundle_path).
/// tinyobjloader reports failure only as a boolean, so the first failure's message is kept in
/// error() for the caller to throw.
class ObjMaterialReader : public tinyobj::MaterialReader {
 public:
  ObjMaterialReader(std::string obj_path, const FileReader& reader);

  bool operator()(const std::string& mtl_name, std::vector<tinyobj::material_t>* materials,
                  std::map<std::string, int>* material_map, std::string* warning,
                  std::string* error) override;

  /// The message of the first MTL file that could not be read, or nullopt.
  const std::optional<std::string>& error() const { return error_; }
  /// Bundle paths of the MTL files read, in order.
  const std::vector<std::string>& files() const { return files_; }

 private:
  std::string obj_path_;
  const FileReader& reader_;
  std::optional<std::string> error_;
  std::vector<std::string> files_;
};

}  // namespace tessera
