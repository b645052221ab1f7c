// Writing a Scene as scene format v1 JSON (docs/scenes.md): what `tessera-worker convert`
// produces from a Mitsuba XML scene.
#pragma once

#include <string>

#include "scene/scene.h"

namespace tessera {

/// The scene as native JSON text that parse_scene reads back to the same Scene: every number
/// is written with the shortest decimal that reads back as the same double (so bit for bit,
/// -0 included), every field explicitly, geometry in world space:
/// - triangle shapes as "triangles" (vertices, indices, and normals when they have some),
///   spheres as "sphere" (center, radius, flip_normals);
/// - every shape names its material; emitters give "emission" (radiance); a shape emitting from
///   both sides is written with "two_sided", which its material must already be (or glass);
/// - materials keep their order and names (an empty or repeated name gets a " #k" suffix).
///
/// What the parser reads back differs only where the native format keeps no such thing:
/// Shape::origin becomes "shapes[i]", flip_normals of triangle shapes (already applied to
/// their winding) becomes false, dropped_triangles 0 and referenced_files empty (the JSON holds
/// all geometry). Normals come back bit for bit when glm::normalize leaves them unchanged,
/// which is how the Mitsuba importer stores them (stable_unit_vector); other normals may move
/// by an ulp, because the parser renormalises.
///
/// `comment`, when not empty, is written as a `//` comment on the first line (one line; control
/// characters are escaped). Throws SceneError for what JSON cannot say: a non-finite number, a
/// shape emitting from both sides with a one-sided material, a triangle shape without
/// triangles, a material index out of range.
std::string write_scene_json(const Scene& scene, const std::string& comment = "");

}  // namespace tessera
