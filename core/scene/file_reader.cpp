// folder_reader (file_reader.h): reading a scene's files from its folder on disk.
#include "scene/file_reader.h"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <system_error>

#include "scene/scene_error.h"
#include "scene/bundle_path.h"

namespace tessera {
namespace fs = std::filesystem;
namespace {

bool is_inside(const fs::path& path, const fs::path& folder) {
  auto [folder_end, path_end] =
      std::mismatch(folder.begin(), folder.end(), path.begin(), path.end());
  return folder_end == folder.end();
}

/// Walks `relative` from `root` component by component: no symlinks anywhere below the root
/// (a bundle must not point outside itself, and the farm copies files, not links).
fs::path resolve_inside(const fs::path& root, const std::string& relative) {
  fs::path full = root;
  for (const fs::path& component : fs::path(relative)) {
    full /= component;
    std::error_code error;
    fs::file_status status = fs::symlink_status(full, error);
    if (!fs::exists(status)) throw SceneError(relative + ": no such file in the scene's folder");
    if (fs::is_symlink(status)) {
      throw SceneError(relative + ": symbolic links are not allowed in a scene's folder");
    }
  }
  std::error_code error;
  fs::path canonical = fs::weakly_canonical(full, error);
  if (error || !is_inside(canonical, root)) {
    throw SceneError(relative + ": resolves outside the scene's folder");
  }
  if (!fs::is_regular_file(canonical)) throw SceneError(relative + ": not a regular file");
  return canonical;
}

}  // namespace

FileReader folder_reader(const fs::path& folder) {
  std::error_code error;
  fs::path root = fs::weakly_canonical(fs::absolute(folder), error);
  if (error) throw SceneError(folder.string() + ": " + error.message());
  return [root](const std::string& relative_path) -> std::string {
    std::string relative = check_bundle_path(relative_path, relative_path);
    fs::path full = resolve_inside(root, relative);
    std::ifstream in(full, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in.is_open() || in.bad()) throw SceneError(relative + ": cannot be read");
    return bytes;
  };
}

}  // namespace tessera
