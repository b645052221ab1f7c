// Helpers shared by the tests that parse scene format v1 text (core/scene/native/ and the
// folders above it).
#pragma once

#include <map>
#include <string>

#include "scene/native/scene_parser.h"
#include "scene/scene.h"
#include "scene/scene_error.h"
#include "scene/scene_test_support.h"

namespace tessera::testing {

/// A scene with a "white" diffuse material and the given shapes (JSON array elements).
inline std::string scene_with_shapes(const std::string& shapes, const std::string& extra = "") {
  return R"({"tessera": 1, "materials": {"white": {"type": "diffuse", "reflectance": [0.8, 0.8, 0.8]},
             "mirror": {"type": "mirror"}, "glass": {"type": "glass"}}, )" +
         extra + R"("shapes": [)" + shapes + "]}";
}

inline Scene parse(const std::string& json, std::map<std::string, std::string> files = {}) {
  return parse_scene(json, memory_reader(std::move(files)));
}

/// The message parse_scene throws for `json`, or "(no error)".
inline std::string error_of(const std::string& json,
                            std::map<std::string, std::string> files = {}) {
  try {
    parse(json, std::move(files));
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace tessera::testing
