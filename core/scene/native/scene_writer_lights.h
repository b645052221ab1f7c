// Internal to write_scene_json (scene_writer.h), in namespace scene_writer: the lights that are
// not shapes (point, spot, directional, constant, envmap, projector).
#pragma once

#include <cstddef>
#include <string>

#include "scene/native/scene_writer_text.h"
#include "scene/scene.h"

namespace tessera::scene_writer {

/// Light `index` as an element of "lights".
std::string light_json(const Light& l, size_t index, const Names& names);

}  // namespace tessera::scene_writer
