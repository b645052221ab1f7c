// The keys of a native "hair" material (docs/scenes.md, "`materials`"): Mitsuba's `hair` parameters.
#pragma once

#include <string_view>
#include <vector>

#include "scene/native/json_value.h"
#include "scene/native/texture_parser.h"
#include "scene/scene.h"

namespace tessera {

/// The keys a hair material takes, "type" and the wrappers' keys included.
std::vector<std::string_view> hair_material_keys();

/// Reads a hair material's own keys into `m` (m.type is hair): "eumelanin" and "pheomelanin"
/// (numbers >= 0, defaults 1.3 and 0.2) or "sigma_a" (a colour >= 0 or a texture with a
/// scale), not both; "ior" (> 0 and != 1; default 1.55 / 1.000277, Mitsuba's amber in air);
/// "longitudinal_roughness", "azimuthal_roughness" (in [0, 1], default 0.3), "scale_tilt"
/// (degrees, any finite number as in Mitsuba, default 2). Throws SceneError naming the JSON path of what is wrong.
void parse_hair_keys(const JsonValue& value, const TextureNames& textures, Material& m);

}  // namespace tessera
