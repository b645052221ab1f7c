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
/// inside it (symlinks that leave the folder are refused). A file whose name ends in ".xml" (any
/// case) is read as a Mitsuba 3 scene (docs/mitsuba.md), any other as scene format v1.
Scene load_scene_file(const std::filesystem::path& scene_file);

/// Parses the text of a scene file named `file_name` (its name at the root of its bundle): a
/// Mitsuba 3 XML scene when the name ends in ".xml" (any case), scene format v1 otherwise.
/// `reader` supplies the files it references. For callers that hold a bundle's bytes rather
/// than files on disk, such as the farm.
Scene parse_scene_any(const std::string& file_name, std::string_view text,
                      const FileReader& reader);

/// A FileReader over a folder on disk, refusing anything that resolves outside it.
FileReader folder_reader(const std::filesystem::path& folder);

/// Checks a relative path as a bundle path; throws SceneError("<context>: ...") when absolute,
/// empty, or containing ".." or empty components. Returns it normalised with '/' separators.
std::string check_bundle_path(const std::string& path, const std::string& context);

}  // namespace tessera
