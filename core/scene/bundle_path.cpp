// check_bundle_path (scene_loader.h): the rule that keeps a scene's files inside its bundle.
#include <algorithm>
#include <cctype>
#include <string>
#include <vector>

#include "scene/native/json_value.h"
#include "scene/scene_error.h"
#include "scene/scene_loader.h"

namespace tessera {
namespace {

bool looks_absolute(const std::string& path) {
  bool drive = path.size() >= 2 && std::isalpha(static_cast<unsigned char>(path[0])) &&
               path[1] == ':';  // "C:..." on Windows
  return path.starts_with('/') || drive;
}

}  // namespace

std::string check_bundle_path(const std::string& path, const std::string& context) {
  auto fail = [&](const std::string& why) {
    throw SceneError(context + ": " + why + " (\"" + printable(path) + "\")");
  };
  if (path.empty()) throw SceneError(context + ": path must not be empty");
  if (path.find('\0') != std::string::npos) fail("path must not contain a NUL character");
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

}  // namespace tessera
