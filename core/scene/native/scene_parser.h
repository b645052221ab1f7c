// The top level of scene format v1 (docs/scenes.md): a JSON object with "tessera": 1.
// native/ builds on the model and mesh/; mitsuba/ and loader/ build on it (the layers: scene.h).
#pragma once

#include <string>
#include <string_view>

#include "scene/file_reader.h"
#include "scene/native/json_value.h"
#include "scene/scene.h"

namespace tessera {

/// Parses scene JSON text. `reader` supplies referenced files (meshes, MTL files). Throws
/// SceneError whose message starts with the JSON path of the offending value.
Scene parse_scene(std::string_view json_text, const FileReader& reader);

/// parse_scene without setting Scene::files: `source_name` names the text in JSON syntax errors
/// (the scene file's name when read from a bundle).
Scene parse_scene_text(std::string_view json_text, const std::string& source_name,
                       const FileReader& reader);

/// Parses the scene object `root`: "tessera" (the format version, 1), "camera", "film",
/// "render", "textures", "materials", "groups", "shapes" and "lights", in that order (so
/// materials may name textures, shapes name materials, textures and groups). Mesh files are
/// read through `reader`. Throws SceneError naming the JSON path of what is wrong.
Scene parse_native_scene(const JsonValue& root, const FileReader& reader);

}  // namespace tessera
