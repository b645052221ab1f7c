// The "materials" object of a scene file (docs/scenes.md, "Materials").
#pragma once

#include "scene/native/json_value.h"
#include "scene/native/material_table.h"

namespace tessera {

/// Parses "materials": an object from name to material, declared into `table` in file order.
/// A material is {"type": "diffuse" (default) | "mirror" | "glass", ...}: diffuse takes
/// "reflectance" ([r,g,b] in [0,1], default 0.5 grey) and "two_sided"; mirror takes
/// "two_sided"; glass takes "ior" (> 0, default 1.5) and is two-sided by nature. Throws
/// SceneError naming the JSON path of what is wrong.
void parse_materials(const JsonValue& materials, MaterialTable& table);

/// Parses one material named `name`.
Material parse_material(const std::string& name, const JsonValue& value);

}  // namespace tessera
