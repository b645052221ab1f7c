// The checks a `volume` texture (Mitsuba's volume texture over a gridvolume or constvolume)
// gets while a scene is read, shared by the native parser and the Mitsuba importer
// (docs/scenes.md, "Volume textures").
#pragma once

#include <memory>
#include <string>
#include <string_view>

#include "scene/volume_grid_file.h"
#include "scene/scene.h"

namespace tessera {

/// The grid of a volume texture's file: parse_volume_grid_file of `bytes` (bundle path `path`),
/// refused with SceneError "<path>: ..." also when it has other than 1 or 3 channels (a surface
/// texture gives a colour or a number; Mitsuba's gridvolume throws at its first lookup of such
/// a grid as a colour).
std::shared_ptr<const VolumeGridFile> read_volume_texture_grid(std::string_view bytes,
                                                               const std::string& path);

/// Checks where the scene's volume textures are used: only materials' colour and scalar
/// parameters (and opacities) may read them, which Tessera looks up at the hit's world position.
/// A bump map is refused (Mitsuba's volume texture has no gradient, eval_1_grad); a normal map,
/// a shape's emission and a light's texture too (Tessera looks those up by (u, v) alone).
/// Throws SceneError naming the user and the texture.
void check_volume_texture_use(const Scene& scene);

}  // namespace tessera
