#include "scene/mitsuba/mitsuba_file_resolver.h"

#include <algorithm>

#include "scene/bundle_path.h"
#include "scene/message_text.h"
#include "scene/scene_error.h"

namespace tessera {

MitsubaFileResolver::MitsubaFileResolver(const FileReader& reader, std::string scene_folder,
                                         std::string root_name)
    : reader_(reader), folders_{std::move(scene_folder)}, root_name_(std::move(root_name)) {}

namespace {

/// True when bundle path `path` lies in bundle folder `folder` ("" or ending in '/') or below.
bool is_below(const std::string& path, const std::string& folder) {
  return path.compare(0, folder.size(), folder) == 0;
}

}  // namespace

void MitsubaFileResolver::prepend(std::string folder) {
  if (confined_to_) confined_to_->push_back(folder);
  folders_.insert(folders_.begin(), std::move(folder));
}

void MitsubaFileResolver::confine_to(std::vector<std::string> folders) {
  confined_to_ = std::move(folders);
}

std::string MitsubaFileResolver::resolve(const MitsubaElement& where, const std::string& filename,
                                         const std::optional<std::string>& first) {
  std::vector<std::string> folders;
  if (first) folders.push_back(*first);
  for (const std::string& f : folders_) {
    if (std::find(folders.begin(), folders.end(), f) == folders.end()) folders.push_back(f);
  }
  std::string first_error;
  for (const std::string& folder : folders) {
    std::string path = join_bundle_path(folder, filename, where.where(), root_name_);
    if (confined_to_ && std::none_of(confined_to_->begin(), confined_to_->end(),
                                     [&](const std::string& f) { return is_below(path, f); })) {
      if (first_error.empty()) {
        first_error = "\"" + printable(filename) +
                      "\" leaves the scene's folder and its <path> folders (a bundle root "
                      "given with --root allows it)";
      }
      continue;
    }
    try {
      std::string bytes = reader_(path);
      cached_path_ = path;
      cached_bytes_ = std::move(bytes);
      return path;
    } catch (const BundleEscapeError&) {
      throw;
    } catch (const SceneError& e) {
      if (first_error.empty()) first_error = e.what();
    }
  }
  if (folders.size() == 1) fail_at(where, first_error);
  std::string searched;
  for (const std::string& f : folders) {
    searched += (searched.empty() ? "" : ", ") + (f.empty() ? std::string("(the root)") : f);
  }
  fail_at(where, "\"" + printable(filename) + "\" is in none of the folders searched (" +
                     searched + "; first: " + first_error + ")");
}

std::string MitsubaFileResolver::read(const std::string& path) {
  if (path == cached_path_) return cached_bytes_;
  return reader_(path);
}

FileReader MitsubaFileResolver::reader() {
  return [this](const std::string& path) { return read(path); };
}

}  // namespace tessera
