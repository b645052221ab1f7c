// Internal to write_scene_json (scene_writer.h), in namespace scene_writer: shapes (triangles,
// spheres, curves, SDF grids, instances) with their geometry in world space.
#pragma once

#include <string>
#include <vector>

#include "scene/native/scene_writer_text.h"
#include "scene/scene.h"

namespace tessera::scene_writer {

/// Shape `s` as an element of "shapes" or of a group's "shapes"; `what` names it in errors.
std::string shape_json(const Shape& s, const std::string& what,
                       const std::vector<Material>& materials, const Names& names);

}  // namespace tessera::scene_writer
