// load_scene_bundle, load_scene_file and parse_scene_any (scene_loader.h): reading a scene file
// from disk, and the choice between scene format v1 and Mitsuba XML by file name.
#include "scene/loader/scene_loader.h"

#include <cctype>
#include <cstdint>
#include <fstream>
#include <iterator>

#include "scene/mitsuba/mitsuba_xml_loader.h"
#include "scene/scene_error.h"
#include "scene/native/scene_parser.h"

namespace tessera {
namespace {

bool is_mitsuba_xml(const std::string& file_name) {
  if (file_name.size() < 4) return false;
  std::string extension = file_name.substr(file_name.size() - 4);
  for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
  return extension == ".xml";
}

std::string read_scene_file(const std::filesystem::path& scene_file) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(scene_file, error);
  if (std::filesystem::is_directory(status)) {
    throw SceneError(scene_file.string() +
                     ": is a folder, not a scene file (give its .json or .xml scene)");
  }
  if (!std::filesystem::exists(status)) throw SceneError(scene_file.string() + ": no such file");
  if (!std::filesystem::is_regular_file(status)) {
    throw SceneError(scene_file.string() + ": not a regular file (a scene must be a .json or .xml file)");
  }
  std::ifstream in(scene_file, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.is_open() || in.bad()) throw SceneError(scene_file.string() + ": cannot be read");
  return text;
}

}  // namespace

Scene load_scene_file(const std::filesystem::path& scene_file,
                      const std::optional<std::filesystem::path>& root,
                      const MitsubaParameters& parameters) {
  return load_scene_bundle(scene_file, root, parameters).scene;
}

SceneOnDisk load_scene_bundle(const std::filesystem::path& scene_file,
                              const std::optional<std::filesystem::path>& root,
                              const MitsubaParameters& parameters) {
  namespace fs = std::filesystem;
  std::string text = read_scene_file(scene_file);
  if (!parameters.empty()) {
    if (!is_mitsuba_xml(scene_file.string())) {
      throw SceneError(scene_file.string() + ": -D " + parameters.front().name +
                       ": -D sets parameters of Mitsuba 3 XML scenes; this is a native scene");
    }
    text = with_mitsuba_parameters(text, scene_file.filename().string(), parameters);
  }
  std::error_code error;
  const fs::path scene = fs::weakly_canonical(fs::absolute(scene_file), error);
  if (error) throw SceneError(scene_file.string() + ": " + error.message());
  SceneOnDisk result;
  result.scene_text = text;
  if (root) {
    result.root = fs::weakly_canonical(fs::absolute(*root), error);
    if (error || !fs::is_directory(result.root)) {
      throw SceneError("--root " + root->string() + ": no such folder");
    }
    fs::path inside = scene.lexically_relative(result.root);
    if (inside.empty() || *inside.begin() == "..") {
      throw SceneError(scene_file.string() + ": the scene file is not inside the bundle root " +
                       result.root.string() + " (--root)");
    }
    result.scene_path = inside.generic_string();
    result.scene = parse_scene_any(result.scene_path, text, folder_reader(result.root),
                                   result.root.string());
    return result;
  }
  // The default root: the scene's folder, widened (for a Mitsuba scene) as far as its paths
  // climb with "..", one reading per widening.
  result.root = scene.parent_path();
  result.scene_path = scene.filename().generic_string();
  for (;;) {
    try {
      result.scene = parse_scene_any(result.scene_path, text, folder_reader(result.root),
                                     result.root.string(), MitsubaReach::scene_folders);
      return result;
    } catch (const BundleEscapeError& escape) {
      fs::path wider = result.root;
      std::string below;
      for (int level = 0; level < escape.levels(); ++level) {
        if (wider == wider.root_path()) throw;
        below = wider.filename().generic_string() + "/" + below;
        wider = wider.parent_path();
      }
      result.root = wider;
      result.scene_path = below + result.scene_path;
    }
  }
}

Scene parse_scene_any(const std::string& file_name, std::string_view text,
                      const FileReader& reader, const std::string& root_name,
                      MitsubaReach reach) {
  // The scene keeps the root's reader: the renderer reads textures and environment maps by
  // their bundle paths through it.
  if (is_mitsuba_xml(file_name)) {
    Scene scene = parse_mitsuba_scene(text, file_name, reader, root_name, reach);
    scene.files = reader;
    return scene;
  }
  // Scene format v1 names files relative to the scene's folder, which need not be the root.
  const size_t slash = file_name.rfind('/');
  const std::string folder = slash == std::string::npos ? "" : file_name.substr(0, slash + 1);
  if (folder.empty()) {
    Scene scene = parse_scene_text(text, file_name, reader);
    scene.files = reader;
    return scene;
  }
  FileReader in_folder = [&](const std::string& path) { return reader(folder + path); };
  Scene scene = parse_scene_text(text, file_name, in_folder);
  for (std::string& path : scene.referenced_files) path = folder + path;
  for (Texture& texture : scene.textures) {
    if (!texture.file.empty()) texture.file = folder + texture.file;
  }
  for (Light& light : scene.lights) {
    if (!light.file.empty()) light.file = folder + light.file;
  }
  scene.files = reader;
  return scene;
}

}  // namespace tessera
