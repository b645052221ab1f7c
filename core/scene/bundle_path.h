// Bundle paths: the rules that keep a scene's files inside its bundle, and the error for a path
// that leaves it.
#pragma once

#include <string>

#include "scene/scene_error.h"

namespace tessera {

/// A path that leaves the bundle root: `levels` more folders above the root would hold it.
/// load_scene_bundle widens a default root by that much and reads the scene again; with a
/// fixed root (--root DIR, a bundle on the farm) it is a refusal like any SceneError.
class BundleEscapeError : public SceneError {
 public:
  BundleEscapeError(const std::string& message, int levels)
      : SceneError(message), levels_(levels) {}
  int levels() const { return levels_; }

 private:
  int levels_;
};

/// Checks a relative path as a bundle path; throws SceneError("<context>: ...") when absolute,
/// empty, or containing ".." or empty components. Returns it normalised with '/' separators.
std::string check_bundle_path(const std::string& path, const std::string& context);

/// The bundle path of `path` as written in a scene file (relative; '\\' or '/' separators; "."
/// and ".." components allowed) read from bundle folder `folder` ("" for the root, else ending
/// in '/'), normalised. Throws SceneError("<context>: ...") for an empty or absolute path, an
/// empty component or no file name, and BundleEscapeError("<context>: ... leaves the bundle
/// root (<root_name>) ...") when ".." climbs above the root.
std::string join_bundle_path(const std::string& folder, const std::string& path,
                             const std::string& context,
                             const std::string& root_name = "the bundle root");

}  // namespace tessera
