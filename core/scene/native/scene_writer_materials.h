// Internal to write_scene_json (scene_writer.h), in namespace scene_writer: materials, textures and
// media.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "scene/native/scene_writer_text.h"
#include "scene/scene.h"

namespace tessera::scene_writer {

/// Material `index` as a "name": {...} member of "materials".
std::string material_json(const Material& m, size_t index, const Names& names);

/// Texture `index` as a "name": {...} member of "textures".
std::string texture_json(const Texture& t, size_t index, const Names& names);

/// Medium `index` as a "name": {...} member of "media"; throws SceneError for a medium the
/// parser would refuse.
std::string medium_json(const Medium& m, size_t index, const Names& names,
                        const std::vector<Texture>& textures);

}  // namespace tessera::scene_writer
