// Which shapes' materials read which mesh attributes, checked once a scene is complete
// (docs/scenes.md, "Mesh attributes").
#pragma once

#include "scene/scene.h"

namespace tessera {

/// Checks every `mesh_attribute` texture of `scene` where it is used: a shape (also one inside
/// a group) whose material (with its back and blended materials) reads attribute A through a
/// colour or scalar parameter or an opacity must have A (Mitsuba throws at render time instead).
/// Such a texture may not feed a normal or bump map (Mitsuba's mesh_attribute has no gradient),
/// a shape's emission or a light (Tessera has no attributes where it samples emitters).
/// Throws SceneError naming the shape, the material, the texture and the attribute.
void check_mesh_attribute_use(const Scene& scene);

}  // namespace tessera
