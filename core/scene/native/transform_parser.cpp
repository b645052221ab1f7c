#include "scene/native/transform_parser.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

namespace tessera {
namespace {

glm::dmat4 parse_scale(const JsonValue& value) {
  glm::dvec3 s;
  if (value.json().is_number()) {
    double k = value.number();
    if (k == 0) value.fail("must be non-zero");
    s = glm::dvec3(k);
  } else {
    s = value.vec3();
    std::vector<JsonValue> xyz = value.elements(3);
    for (int i = 0; i < 3; ++i) {
      if (s[i] == 0) xyz[i].fail("must be non-zero");
    }
  }
  return glm::scale(glm::dmat4(1.0), s);
}

glm::dmat4 parse_rotate(const JsonValue& value) {
  value.expect_object({"axis", "angle"}, "a rotation");
  JsonValue axis_value = value.at("axis");
  glm::dvec3 axis = axis_value.vec3();
  double length = glm::length(axis);
  if (!(length > 0) || !std::isfinite(length)) axis_value.fail("must be a non-zero vector");
  double angle_deg = value.at("angle").number();
  return glm::rotate(glm::dmat4(1.0), glm::radians(angle_deg), axis / length);
}

glm::dmat4 parse_translate(const JsonValue& value) {
  return glm::translate(glm::dmat4(1.0), value.vec3());
}

/// A 4x4 row-major matrix; glm is column-major, so element (row r, column c) goes to m[c][r].
glm::dmat4 parse_matrix(const JsonValue& value) {
  std::vector<JsonValue> rows = value.elements(4);
  glm::dmat4 m(1.0);
  for (int r = 0; r < 4; ++r) {
    std::vector<JsonValue> row = rows[r].elements(4);
    for (int c = 0; c < 4; ++c) m[c][r] = row[c].number();
  }
  if (m[0][3] != 0 || m[1][3] != 0 || m[2][3] != 0 || m[3][3] != 1) {
    rows[3].fail("must be [0, 0, 0, 1] (the transform must be affine)");
  }
  glm::dmat3 l(m);
  double largest = 0;
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) largest = std::max(largest, std::abs(l[c][r]));
  }
  double det = glm::determinant(l);
  if (!(std::abs(det) > 1e-12 * largest * largest * largest) || !std::isfinite(det)) {
    value.fail("must be invertible (its 3x3 part is singular)");
  }
  return m;
}

/// One object: "matrix" alone, or scale, then rotate, then translate.
glm::dmat4 parse_step(const JsonValue& value) {
  value.expect_object({"scale", "rotate", "translate", "matrix"}, "a transform");
  if (std::optional<JsonValue> matrix = value.find("matrix")) {
    if (value.has("scale") || value.has("rotate") || value.has("translate")) {
      matrix->fail(
          "cannot be combined with scale, rotate or translate in one object (use an array of "
          "transforms)");
    }
    return parse_matrix(*matrix);
  }
  glm::dmat4 m(1.0);
  if (std::optional<JsonValue> s = value.find("scale")) m = parse_scale(*s) * m;
  if (std::optional<JsonValue> r = value.find("rotate")) m = parse_rotate(*r) * m;
  if (std::optional<JsonValue> t = value.find("translate")) m = parse_translate(*t) * m;
  return m;
}

}  // namespace

Transform parse_transform(const JsonValue& value) {
  glm::dmat4 m(1.0);
  if (value.json().is_array()) {
    for (const JsonValue& step : value.elements()) m = parse_step(step) * m;
  } else {
    m = parse_step(value);
  }
  double det = glm::determinant(glm::dmat3(m));
  if (det == 0 || !std::isfinite(det)) value.fail("is singular or overflows (check the scales)");
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      if (!std::isfinite(m[c][r])) value.fail("overflows (check the scales)");
    }
  }
  return Transform(m);
}

}  // namespace tessera
