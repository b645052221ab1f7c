// Mitsuba's curve files, as its `linearcurve` and `bsplinecurve` shapes read them: one control
// point per line, "x y z radius"; an empty line (or one of spaces, tabs and carriage returns)
// ends a curve; a linear curve needs at least 2 control points, a B-spline at least 4.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec4.hpp>

#include "scene/scene.h"

namespace tessera {

/// The curves of one file, in the file's own space.
struct CurveFile {
  /// (x, y, z, radius) per control point, all curves one after another. The values are the
  /// file's numbers rounded to float (Mitsuba reads them with strtof), then widened.
  std::vector<glm::dvec4> control_points;
  /// Control points per curve, in file order; they sum to control_points.size().
  std::vector<uint32_t> curve_sizes;
};

/// The fewest control points a curve of `basis` has: 2 linear, 4 B-spline (one segment).
uint32_t min_curve_points(CurveBasis basis);
/// The segments of a curve of `points` control points: points - 1 (linear) or points - 3
/// (B-spline), Mitsuba's segment indices; 0 below min_curve_points.
inline uint32_t curve_segment_count(CurveBasis basis, uint32_t points) {
  const uint32_t min_points = min_curve_points(basis);
  return points < min_points ? 0 : points - min_points + 1;
}

/// Reads the text of a curve file whose bundle path is `path` (for messages). Each line holds
/// four numbers (x, y, z, radius) separated by spaces or tabs, and nothing else; positions and
/// radii must be finite floats and radii >= 0 (Mitsuba's bsplinecurve closes a tube with
/// radius 0 at its ends). Throws SceneError "<path>: line <L>: ..." for a bad line or a curve
/// with too few control points (the line where it starts), and "<path>: ..." for a file without
/// control points.
CurveFile parse_curve_file(std::string_view text, const std::string& path, CurveBasis basis);

}  // namespace tessera
