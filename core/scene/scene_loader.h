// Parsing scene format v1 (docs/scenes.md) into a Scene.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

#include "scene/scene.h"

namespace tessera {

/// Reads a file the scene references, given its path relative to the scene file's folder
/// (already checked: relative, '/'-separated, no "..", no empty component). Returns the bytes;
/// throws SceneError naming the path when it is missing or unreadable.
using FileReader = std::function<std::string(const std::string& relative_path)>;

/// Parses scene JSON text. `reader` supplies referenced files (meshes, MTL files). Throws
/// SceneError whose message starts with the JSON path of the offending value.
Scene parse_scene(std::string_view json_text, const FileReader& reader);

/// Loads a scene file from disk; referenced files are read relative to its folder and must stay
/// inside it (symlinks that leave the folder are refused).
Scene load_scene_file(const std::filesystem::path& scene_file);

/// A FileReader over a folder on disk, refusing anything that resolves outside it.
FileReader folder_reader(const std::filesystem::path& folder);

/// Checks a relative path as a bundle path; throws SceneError("<context>: ...") when absolute,
/// empty, or containing ".." or empty components. Returns it normalised with '/' separators.
std::string check_bundle_path(const std::string& path, const std::string& context);

}  // namespace tessera
