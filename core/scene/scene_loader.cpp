// parse_scene, load_scene_file and parse_scene_any (scene_loader.h): the top level of scene format
// v1, and the choice between it and Mitsuba XML by file name.
#include "scene/scene_loader.h"

#include <cctype>
#include <cstdint>
#include <fstream>
#include <iterator>

#include "scene/native/json_document.h"
#include "scene/native/json_value.h"
#include "scene/mitsuba/mitsuba_xml_loader.h"
#include "scene/scene_error.h"
#include "scene/native/scene_parser.h"

namespace tessera {
namespace {

/// Parses scene text; `source_name` names it in JSON syntax errors.
Scene parse_scene_text(std::string_view json_text, const std::string& source_name,
                       const FileReader& reader) {
  Json document = parse_json_document(json_text, source_name);
  if (!document.is_object()) {
    throw SceneError(source_name + ": a scene must be a JSON object ({\"tessera\": 1, ...})");
  }
  JsonValue root(document, "");
  return parse_native_scene(root, reader);
}

bool is_mitsuba_xml(const std::string& file_name) {
  if (file_name.size() < 4) return false;
  std::string extension = file_name.substr(file_name.size() - 4);
  for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
  return extension == ".xml";
}

std::string read_scene_file(const std::filesystem::path& scene_file) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(scene_file, error)) {
    throw SceneError(scene_file.string() + ": no such file");
  }
  std::ifstream in(scene_file, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.is_open() || in.bad()) throw SceneError(scene_file.string() + ": cannot be read");
  return text;
}

}  // namespace

Scene parse_scene(std::string_view json_text, const FileReader& reader) {
  Scene scene = parse_scene_text(json_text, "scene", reader);
  scene.files = reader;
  return scene;
}

Scene load_scene_file(const std::filesystem::path& scene_file) {
  std::string text = read_scene_file(scene_file);
  std::filesystem::path folder = scene_file.parent_path();
  if (folder.empty()) folder = ".";
  return parse_scene_any(scene_file.filename().string(), text, folder_reader(folder));
}

Scene parse_scene_any(const std::string& file_name, std::string_view text,
                      const FileReader& reader) {
  Scene scene = is_mitsuba_xml(file_name) ? parse_mitsuba_scene(text, file_name, reader)
                                           : parse_scene_text(text, file_name, reader);
  scene.files = reader;
  return scene;
}

}  // namespace tessera
