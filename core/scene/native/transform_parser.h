// The "transform" key of a shape (docs/scenes.md, "Transforms").
#pragma once

#include "scene/native/json_value.h"
#include "scene/transform.h"

namespace tessera {

/// Parses a transform: one object or an array of objects, the first applied first. An object
/// holds any of "scale" (number or [x,y,z], non-zero), "rotate" ({"axis": [x,y,z], "angle":
/// degrees}, right-handed), "translate" ([x,y,z]), applied in that order; or only "matrix"
/// (4x4, row-major, affine, invertible). Throws SceneError naming the offending JSON path.
Transform parse_transform(const JsonValue& value);

}  // namespace tessera
