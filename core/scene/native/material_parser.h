// The "materials" object of a scene file (docs/scenes.md, "`materials`").
#pragma once

#include "scene/native/json_value.h"
#include "scene/native/material_table.h"
#include "scene/native/texture_parser.h"

namespace tessera {

/// Parses "materials": an object from name to material, declared into `table` in file order.
/// A material is {"type": one of diffuse (default), mirror, glass, conductor, rough_conductor,
/// rough_glass, thin_glass, plastic, rough_plastic, and the keys of that type (Mitsuba's
/// parameter names; docs/scenes.md lists them)}. Colours and roughness may name `textures`.
/// "back" names the (two-sided) material seen from the back. Throws SceneError naming the JSON
/// path of what is wrong.
void parse_materials(const JsonValue& materials, MaterialTable& table,
                     const TextureNames& textures);

/// Parses one material named `name` ("back" is resolved by parse_materials).
Material parse_material(const std::string& name, const JsonValue& value,
                        const TextureNames& textures);

/// Glass, rough glass and thin glass: two-sided by nature.
bool is_glass_kind(MaterialType type);

}  // namespace tessera
