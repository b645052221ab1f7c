// The "media" object of a scene file and the references to it (docs/scenes.md, "Media").
#pragma once

#include <map>
#include <string>
#include <vector>

#include "scene/native/json_value.h"
#include "scene/native/texture_parser.h"
#include "scene/scene.h"

namespace tessera {

/// Medium name -> index into Scene::media.
using MediumNames = std::map<std::string, int32_t>;

/// Parses "media": an object from name to medium, appended to `media` in file order. A medium is
/// {"type": "homogeneous" (default) or "heterogeneous", "sigma_t", "albedo", "scale",
/// "phase": {"type": "isotropic"} or {"type": "hg", "g"}, "sample_emitters"}. A homogeneous
/// medium's sigma_t is [r, g, b]; its albedo and a heterogeneous one's sigma_t and albedo may
/// be {"texture": a volume texture, "scale"}. Throws SceneError naming the JSON path of what is wrong (sigma_t < 0,
/// albedo outside [0, 1], |g| >= 1, scale < 0, a texture that is not a volume).
MediumNames parse_media(const JsonValue& value, const std::vector<Texture>& textures,
                        const TextureNames& texture_names, std::vector<Medium>& media);

/// The index of the medium a string value names; fails naming the value when unknown.
int32_t medium_index(const JsonValue& value, const MediumNames& media);

/// The problem with medium `m` (its values out of range), "" when none: for the writer and
/// for media made by the Mitsuba importer. `textures` are the scene's; nullptr skips the
/// check that textured values name volume textures.
std::string medium_problem(const Medium& m, const std::vector<Texture>* textures);

}  // namespace tessera
