#include "scene/mesh/curve_file.h"

#include <charconv>
#include <cmath>

#include "scene/message_text.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

/// The line as a message shows it: at most 60 characters, control characters escaped.
std::string quoted(std::string_view line) {
  constexpr size_t kMax = 60;
  std::string shown = printable(line.substr(0, kMax));
  return "\"" + shown + (line.size() > kMax ? "...\"" : "\"");
}

/// One control point "x y z radius" (blank-separated, nothing after); throws with the reason.
glm::dvec4 parse_point(std::string_view line, const std::string& where) {
  float values[4];
  const char* cur = line.data();
  const char* end = line.data() + line.size();
  for (int i = 0; i < 4; ++i) {
    while (cur < end && is_blank(*cur)) ++cur;
    // strtof, which Mitsuba uses, takes a leading '+'; from_chars does not.
    if (cur < end && *cur == '+') ++cur;
    auto [next, error] = std::from_chars(cur, end, values[i]);
    if (error == std::errc::result_out_of_range) {
      throw SceneError(where + ": " + quoted(line) + ": a number out of float range");
    }
    if (error != std::errc() || (next < end && !is_blank(*next))) {
      throw SceneError(where + ": " + quoted(line) +
                       ": expected four numbers \"x y z radius\" (Mitsuba's curve format)");
    }
    cur = next;
  }
  while (cur < end && is_blank(*cur)) ++cur;
  if (cur != end) {
    throw SceneError(where + ": " + quoted(line) +
                     ": more than four numbers \"x y z radius\" on a line");
  }
  if (!std::isfinite(values[0]) || !std::isfinite(values[1]) || !std::isfinite(values[2])) {
    throw SceneError(where + ": the position is not finite");
  }
  if (!std::isfinite(values[3]) || values[3] < 0) {
    throw SceneError(where + ": the radius must be finite and >= 0 (got " +
                     format_number(values[3]) + ")");
  }
  return glm::dvec4(values[0], values[1], values[2], values[3]);
}

}  // namespace

uint32_t min_curve_points(CurveBasis basis) { return basis == CurveBasis::linear ? 2 : 4; }

CurveFile parse_curve_file(std::string_view text, const std::string& path, CurveBasis basis) {
  CurveFile file;
  const uint32_t min_points = min_curve_points(basis);
  const char* kind = basis == CurveBasis::linear ? "a linear curve" : "a B-spline curve";
  uint32_t current = 0;     // control points of the curve being read
  size_t current_line = 0;  // where it starts
  auto finish_curve = [&]() {
    if (current == 0) return;
    if (current < min_points) {
      throw SceneError(path + ": line " + std::to_string(current_line) + ": " + kind +
                       " needs at least " + std::to_string(min_points) +
                       " control points (this one has " + std::to_string(current) +
                       "; an empty line starts a new curve)");
    }
    file.curve_sizes.push_back(current);
    current = 0;
  };
  size_t line_number = 0;
  size_t start = 0;
  while (start < text.size()) {
    size_t newline = text.find('\n', start);
    if (newline == std::string_view::npos) newline = text.size();
    std::string_view line = text.substr(start, newline - start);
    start = newline + 1;
    ++line_number;
    size_t first = 0;
    while (first < line.size() && is_blank(line[first])) ++first;
    if (first == line.size()) {
      finish_curve();
      continue;
    }
    if (current == 0) current_line = line_number;
    if (current == UINT32_MAX) {
      throw SceneError(path + ": line " + std::to_string(line_number) + ": curve too long");
    }
    const std::string where = path + ": line " + std::to_string(line_number);
    file.control_points.push_back(parse_point(line, where));
    ++current;
  }
  finish_curve();
  if (file.control_points.empty()) {
    throw SceneError(path + ": no control points (an empty curve file)");
  }
  return file;
}

}  // namespace tessera
