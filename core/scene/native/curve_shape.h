// A "curves" shape of a scene file (docs/scenes.md, "`curves`"): round tubes along control
// points, from a Mitsuba curve file or written out inline.
#pragma once

#include "scene/native/json_value.h"
#include "scene/native/shape_parser.h"
#include "scene/scene.h"
#include "scene/transform.h"

namespace tessera {

/// Parses {"type": "curves", "basis": "linear" | "bspline", "material", "two_sided",
/// "transform"} with either "file" (a Mitsuba curve file, scene/mesh/curve_file.h) or
/// "control_points" ([[x, y, z, radius], ...]) and "curve_sizes" (control points per curve;
/// default: one curve of them all). The transform moves the positions and leaves the radii as
/// they are (Mitsuba's rule). Throws SceneError naming the JSON path (and the file's line).
Shape parse_curve_shape(const JsonValue& value, ShapeContext& context);

/// Moves `points` by `to_world` (radii unchanged) and checks that they stay finite; `where`
/// names the transform in the message.
void place_curve_points(std::vector<glm::dvec4>& points, const Transform& to_world,
                        const std::string& where);

}  // namespace tessera
