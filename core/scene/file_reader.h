// Reading the files of a scene's bundle (docs/mitsuba.md, "Files, bundles and paths"): what every
// scene format reads its meshes, images and included files through.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

namespace tessera {

/// Reads a file of the scene's bundle, given its bundle path: relative to the bundle root,
/// already checked ('/'-separated, no "..", no empty component). The scene file's own folder is
/// the root unless the bundle root lies above it (see load_scene_bundle). Returns the bytes;
/// throws SceneError naming the path when it is missing or unreadable.
using FileReader = std::function<std::string(const std::string& bundle_path)>;

/// A FileReader over a folder on disk, refusing anything that resolves outside it and symbolic
/// links anywhere below it.
FileReader folder_reader(const std::filesystem::path& folder);

}  // namespace tessera
