#include "scene/mitsuba/mitsuba_transform.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <numbers>
#include <optional>

#include "scene/message_text.h"
#include "scene/mitsuba/mitsuba_values.h"

namespace tessera {
namespace {

void expect_only(const MitsubaElement& op, std::initializer_list<std::string_view> allowed) {
  for (const auto& [name, value] : op.attributes) {
    if (std::find(allowed.begin(), allowed.end(), name) == allowed.end()) {
      fail_at(op, "unexpected attribute \"" + printable(name) + "\"");
    }
  }
  if (!op.children.empty()) fail_at(op.children.front(), "unexpected inside " + op.label());
}

double number_attribute(const MitsubaElement& op, std::string_view name, double fallback) {
  const std::string* text = op.attribute(name);
  if (!text) return fallback;
  std::optional<double> value = parse_mitsuba_float(*text);
  if (!value) {
    fail_at(op, std::string(name) + " must be a number (got \"" + printable(*text) + "\")");
  }
  return *value;
}

/// value="v" or value="x, y, z", or x/y/z attributes defaulting to `fallback`.
glm::dvec3 xyz_attributes(const MitsubaElement& op, double fallback) {
  const std::string* value = op.attribute("value");
  if (!value) {
    return {number_attribute(op, "x", fallback), number_attribute(op, "y", fallback),
            number_attribute(op, "z", fallback)};
  }
  if (op.attribute("x") || op.attribute("y") || op.attribute("z")) {
    fail_at(op, "give either value or x/y/z, not both");
  }
  if (std::optional<std::vector<double>> one = parse_mitsuba_floats(*value, 1)) {
    return glm::dvec3((*one)[0]);
  }
  std::optional<std::vector<double>> three = parse_mitsuba_floats(*value, 3);
  if (!three) {
    fail_at(op, "value must be one number or three (got \"" + printable(*value) + "\")");
  }
  return {(*three)[0], (*three)[1], (*three)[2]};
}

/// A required "x, y, z" attribute of <lookat>.
glm::dvec3 point_attribute(const MitsubaElement& op, std::string_view name) {
  const std::string* text = op.attribute(name);
  if (!text) fail_at(op, "missing attribute \"" + std::string(name) + "\"");
  std::optional<std::vector<double>> v = parse_mitsuba_floats(*text, 3);
  if (!v) {
    fail_at(op, std::string(name) + " must be three numbers (got \"" + printable(*text) + "\")");
  }
  return {(*v)[0], (*v)[1], (*v)[2]};
}

/// The matrix of row-major values (16, or 9 for the linear part).
glm::dmat4 matrix_of(const MitsubaElement& op) {
  expect_only(op, {"value"});
  const std::string* text = op.attribute("value");
  if (!text) fail_at(op, "missing attribute \"value\"");
  std::vector<std::string_view> items = split_mitsuba_list(*text);
  if (items.size() != 16 && items.size() != 9) {
    fail_at(op, "value must have 16 numbers (or 9), got " + std::to_string(items.size()));
  }
  int n = items.size() == 16 ? 4 : 3;
  glm::dmat4 m(1.0);
  for (int row = 0; row < n; ++row) {
    for (int col = 0; col < n; ++col) {
      std::optional<double> v = parse_mitsuba_float(items[size_t(row * n + col)]);
      if (!v) {
        fail_at(op, "\"" + printable(items[size_t(row * n + col)]) + "\" is not a number");
      }
      m[col][row] = *v;  // glm is column-major
    }
  }
  if (m[0][3] != 0 || m[1][3] != 0 || m[2][3] != 0 || m[3][3] != 1) {
    fail_at(op, "the last row must be 0 0 0 1 (Tessera takes affine transforms only)");
  }
  return m;
}

/// Mitsuba's coordinate_system(n) (Duff et al. 2017): the first vector orthogonal to unit n.
glm::dvec3 orthogonal_to(const glm::dvec3& n) {
  double sign = std::copysign(1.0, n.z);
  double a = -1.0 / (sign + n.z);
  double b = n.x * n.y * a;
  return {1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x};
}

glm::dmat4 lookat_of(const MitsubaElement& op) {
  expect_only(op, {"origin", "target", "up"});
  glm::dvec3 origin = point_attribute(op, "origin");
  glm::dvec3 target = point_attribute(op, "target");
  glm::dvec3 up(0);
  if (op.attribute("up")) up = point_attribute(op, "up");
  if (up == glm::dvec3(0)) up = orthogonal_to(glm::normalize(target - origin));
  glm::dmat4 m = mitsuba_look_at(origin, target, up);
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      if (!std::isfinite(m[c][r])) {
        fail_at(op, "undefined: origin equals target, or up is parallel to the view direction");
      }
    }
  }
  return m;
}

/// Mitsuba builds a rotation's matrix from the axis as written, so an axis that is not of unit
/// length scales and shears too (mitsuba-data's scenes/hello.xml turns about (0, 1, 1)). Tessera
/// builds the same matrix and says so, since the scene's author likely meant a pure rotation.
/// Written decimals of a unit axis (0.57735 for 1/sqrt(3)) are within the tolerance.
void note_non_unit_axis(const MitsubaElement& op, const glm::dvec3& axis) {
  const double length = glm::length(axis);
  if (std::abs(length - 1.0) <= 1e-6) return;
  std::fprintf(stderr,
               "note: %s: line %d: %s: the rotation axis (%g, %g, %g) is not of unit length "
               "(length %g): Mitsuba 3 builds the matrix from the axis as written, which scales "
               "and shears as well as it turns, and so does Tessera\n",
               op.file.c_str(), op.line, op.label().c_str(), axis.x, axis.y, axis.z, length);
}

glm::dmat4 operation(const MitsubaElement& op) {
  if (op.tag == "translate") {
    expect_only(op, {"x", "y", "z", "value"});
    glm::dmat4 m(1.0);
    m[3] = glm::dvec4(xyz_attributes(op, 0.0), 1.0);
    return m;
  }
  if (op.tag == "scale") {
    expect_only(op, {"x", "y", "z", "value"});
    glm::dvec3 s = xyz_attributes(op, 1.0);
    if (s.x == 0 || s.y == 0 || s.z == 0) fail_at(op, "scale factors must be non-zero");
    glm::dmat4 m(1.0);
    m[0][0] = s.x;
    m[1][1] = s.y;
    m[2][2] = s.z;
    return m;
  }
  if (op.tag == "rotate") {
    expect_only(op, {"x", "y", "z", "value", "angle"});
    if (!op.attribute("angle")) fail_at(op, "missing attribute \"angle\" (degrees)");
    glm::dvec3 axis = xyz_attributes(op, 0.0);
    if (axis == glm::dvec3(0)) fail_at(op, "the rotation axis must not be zero");
    note_non_unit_axis(op, axis);
    return mitsuba_rotate(axis, number_attribute(op, "angle", 0));
  }
  if (op.tag == "matrix") return matrix_of(op);
  if (op.tag == "lookat") return lookat_of(op);
  fail_at(op,
          "not a transform operation (Tessera reads translate, rotate, scale, matrix and "
          "lookat)");
}

}  // namespace

glm::dmat4 mitsuba_look_at(const glm::dvec3& origin, const glm::dvec3& target,
                           const glm::dvec3& up) {
  glm::dvec3 dir = glm::normalize(target - origin);
  glm::dvec3 left = glm::normalize(glm::cross(up, dir));
  glm::dvec3 new_up = glm::cross(dir, left);
  return glm::dmat4(glm::dvec4(left, 0), glm::dvec4(new_up, 0), glm::dvec4(dir, 0),
                    glm::dvec4(origin, 1));
}

glm::dmat4 mitsuba_rotate(const glm::dvec3& axis, double angle_deg) {
  double radians = angle_deg * (std::numbers::pi / 180.0);
  double s = std::sin(radians), c = std::cos(radians), cm = 1.0 - c;
  // Not normalised: Mitsuba 3 (drjit's rotate) uses the axis as written.
  double x = axis.x, y = axis.y, z = axis.z;
  glm::dmat4 m(1.0);  // m[col][row]
  m[0][0] = x * x * cm + c;
  m[1][0] = x * y * cm - z * s;
  m[2][0] = x * z * cm + y * s;
  m[0][1] = x * y * cm + z * s;
  m[1][1] = y * y * cm + c;
  m[2][1] = y * z * cm - x * s;
  m[0][2] = x * z * cm - y * s;
  m[1][2] = y * z * cm + x * s;
  m[2][2] = z * z * cm + c;
  return m;
}

Transform read_mitsuba_transform(const MitsubaElement& transform) {
  glm::dmat4 m(1.0);
  for (const MitsubaElement& op : transform.children) m = operation(op) * m;
  double det = glm::determinant(glm::dmat3(m));
  bool finite = std::isfinite(det);
  double largest = 0;
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 3; ++r) {
      finite = finite && std::isfinite(m[c][r]);
      if (c < 3) largest = std::max(largest, std::abs(m[c][r]));
    }
  }
  if (!finite) fail_at(transform, "the composed transform overflows");
  // Relative to its size, as the native parser checks matrices (docs/scenes.md).
  if (!(std::abs(det) > 1e-12 * largest * largest * largest)) {
    fail_at(transform, "the composed transform is singular (not invertible)");
  }
  return Transform(m);
}

}  // namespace tessera
