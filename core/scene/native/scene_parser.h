// The top level of scene format v1 (docs/scenes.md): a JSON object with "tessera": 1.
#pragma once

#include "scene/native/json_value.h"
#include "scene/scene.h"
#include "scene/scene_loader.h"

namespace tessera {

/// Parses the scene object `root`: "tessera" (the format version, 1), "camera", "film",
/// "render", "textures", "materials", "groups", "shapes" and "lights", in that order (so
/// materials may name textures, shapes name materials, textures and groups). Mesh files are
/// read through `reader`. Throws SceneError naming the JSON path of what is wrong.
Scene parse_native_scene(const JsonValue& root, const FileReader& reader);

}  // namespace tessera
