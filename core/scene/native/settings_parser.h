// The "camera", "film" and "render" objects of a scene file (docs/scenes.md).
#pragma once

#include "scene/native/json_value.h"
#include "scene/scene.h"

namespace tessera {

/// "camera": position, look_at, up (3-vectors; position != look_at, up not parallel to the
/// view direction), fov (full angle in degrees, in (0, 180)), fov_axis ("x" default, "y",
/// "smaller", "larger"), aperture_radius (>= 0, default 0), focus_distance (> 0, default 1).
/// Absent keys keep Camera's defaults.
Camera parse_camera(const JsonValue& value);

/// "film": width and height, integers in [1, 32768], default 256.
Film parse_film(const JsonValue& value);

/// "render": spp (integer >= 1, default 64), max_depth (-1 = unbounded, the default, or >= 1),
/// rr_depth (integer >= 1, default kDefaultRrDepth), seed (integer >= 0, default 0),
/// hide_emitters (default false).
RenderSettings parse_render(const JsonValue& value);

}  // namespace tessera
