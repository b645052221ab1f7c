// The "lights" array of a scene file: emitters that are not shapes (docs/scenes.md, "Lights").
#pragma once

#include <string>
#include <vector>

#include "scene/native/json_value.h"
#include "scene/native/texture_parser.h"
#include "scene/scene.h"

namespace tessera {

/// Parses "lights": an array of {"type": point | spot | directional | constant | envmap, ...}
/// (point, spot: "intensity"; spot: "cutoff_angle", "beam_width" and "texture", the name of
/// one of `textures` projected over the cone (Light::texture); directional: "irradiance";
/// constant: "radiance"; envmap: "file", "scale"; projector: "irradiance" (with a texture:
/// its scale), "texture", "fov" (horizontal, degrees, required) and "aspect" (1); all but
/// constant: "transform", which must be rigid). Envmap files are checked with check_bundle_path and added to `referenced_files`.
/// Throws SceneError naming the JSON path of what is wrong.
std::vector<Light> parse_lights(const JsonValue& value, const TextureNames& textures,
                               std::vector<std::string>& referenced_files);

}  // namespace tessera
