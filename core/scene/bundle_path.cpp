// check_bundle_path and join_bundle_path (bundle_path.h): the rules that keep a scene's files
// inside its bundle.
#include "scene/bundle_path.h"

#include <algorithm>
#include <cctype>
#include <string>
#include <vector>

#include "scene/message_text.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

bool looks_absolute(const std::string& path) {
  bool drive = path.size() >= 2 && std::isalpha(static_cast<unsigned char>(path[0])) &&
               path[1] == ':';  // "C:..." on Windows
  return path.starts_with('/') || drive;
}

/// A byte below 0x20 or DEL: no file of a scene's bundle is named so, and the name would break
/// the one-line error messages that quote it.
bool has_control_character(const std::string& path) {
  return std::any_of(path.begin(), path.end(), [](char c) {
    const auto b = static_cast<unsigned char>(c);
    return b < 0x20 || b == 0x7f;
  });
}

}  // namespace

std::string check_bundle_path(const std::string& path, const std::string& context) {
  auto fail = [&](const std::string& why) {
    throw SceneError(context + ": " + why + " (\"" + printable(path) + "\")");
  };
  if (path.empty()) throw SceneError(context + ": path must not be empty");
  if (path.find('\0') != std::string::npos) fail("path must not contain a NUL character");
  if (has_control_character(path)) fail("path must not contain a control character");
  std::string slashed = path;
  for (char& c : slashed) c = c == '\\' ? '/' : c;
  if (looks_absolute(slashed)) fail("path must be relative to the scene's folder");
  std::string normalised;
  size_t start = 0;
  while (start <= slashed.size()) {
    size_t end = std::min(slashed.find('/', start), slashed.size());
    std::string component = slashed.substr(start, end - start);
    if (component.empty()) fail("path must not have an empty component");
    if (component == "..") fail("path must stay inside the scene's folder");
    if (component != ".") normalised += (normalised.empty() ? "" : "/") + component;
    start = end + 1;
  }
  if (normalised.empty()) fail("path must name a file");
  return normalised;
}

std::string join_bundle_path(const std::string& folder, const std::string& path,
                             const std::string& context, const std::string& root_name) {
  auto fail = [&](const std::string& why) {
    throw SceneError(context + ": \"" + printable(path) + "\" " + why);
  };
  if (path.empty()) throw SceneError(context + ": path must not be empty");
  if (path.find('\0') != std::string::npos) fail("must not contain a NUL character");
  if (has_control_character(path)) fail("must not contain a control character");
  std::string slashed = path;
  for (char& c : slashed) c = c == '\\' ? '/' : c;
  if (looks_absolute(slashed)) {
    fail("is absolute: paths are relative to the file that names them and stay inside the "
         "bundle root (" + root_name + ")");
  }
  std::vector<std::string> components;
  int escaped = 0;  // ".." components above the root
  auto push = [&](const std::string& all, bool user) {
    size_t start = 0;
    while (start <= all.size()) {
      size_t end = std::min(all.find('/', start), all.size());
      std::string component = all.substr(start, end - start);
      start = end + 1;
      if (component.empty()) {
        if (user && end < all.size()) fail("must not have an empty component");
        if (user) fail("must name a file");
        continue;
      }
      if (component == ".") continue;
      if (component == "..") {
        if (components.empty()) {
          ++escaped;
        } else {
          components.pop_back();
        }
        continue;
      }
      components.push_back(component);
    }
  };
  push(folder, false);
  push(slashed, true);
  if (escaped > 0) {
    throw BundleEscapeError(context + ": \"" + printable(path) + "\" leaves the bundle root (" +
                                root_name +
                                "): every file a scene names must be inside it (render, convert "
                                "and submit take --root DIR to widen it)",
                            escaped);
  }
  if (components.empty()) fail("must name a file");
  std::string joined;
  for (const std::string& c : components) joined += (joined.empty() ? "" : "/") + c;
  return joined;
}

}  // namespace tessera
