#include "scene/native/curve_shape.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "scene/bundle_path.h"
#include "scene/mesh/curve_file.h"
#include "scene/native/transform_parser.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

CurveBasis parse_basis(const JsonValue& value) {
  std::optional<JsonValue> basis = value.find("basis");
  if (!basis) return CurveBasis::linear;
  const std::string& name = basis->string();
  if (name == "linear") return CurveBasis::linear;
  if (name == "bspline") return CurveBasis::bspline;
  basis->fail("unknown curve basis \"" + printable(name) + "\" (expected linear or bspline)");
}

/// The inline control points and curve sizes of `value` into `shape`.
void read_inline(const JsonValue& value, Shape& shape) {
  JsonValue points = value.at("control_points");
  for (const JsonValue& p : points.elements()) {
    std::vector<JsonValue> xyzr = p.elements(4);
    glm::dvec4 cp(xyzr[0].number(), xyzr[1].number(), xyzr[2].number(), xyzr[3].number());
    if (!(cp.w >= 0)) xyzr[3].fail("a radius must be >= 0 (got " + format_number(cp.w) + ")");
    shape.control_points.push_back(cp);
  }
  if (shape.control_points.empty()) points.fail("needs at least one curve");
  const uint32_t min_points = min_curve_points(shape.curve_basis);
  const uint64_t total = shape.control_points.size();
  std::optional<JsonValue> sizes = value.find("curve_sizes");
  if (!sizes) {
    if (total < min_points) {
      points.fail(std::string(shape.curve_basis == CurveBasis::linear ? "a linear" : "a bspline") +
                  " curve needs at least " +
                  std::to_string(min_points) + " control points");
    }
    shape.curve_sizes.push_back(uint32_t(total));
    return;
  }
  uint64_t sum = 0;
  for (const JsonValue& n : sizes->elements()) {
    const auto count = uint32_t(n.integer(min_points, UINT32_MAX));
    shape.curve_sizes.push_back(count);
    sum += count;
  }
  if (sum != total) {
    sizes->fail("the curves have " + std::to_string(sum) + " control points in all, but " +
                std::to_string(total) + " are given");
  }
}

}  // namespace

void place_curve_points(std::vector<glm::dvec4>& points, const Transform& to_world,
                        const std::string& where) {
  for (glm::dvec4& cp : points) {
    const glm::dvec3 p = to_world.point(glm::dvec3(cp));
    if (!std::isfinite(p.x + p.y + p.z)) {
      throw SceneError(where + ": a control point overflows after the transform");
    }
    cp = glm::dvec4(p, cp.w);
  }
}

Shape parse_curve_shape(const JsonValue& value, ShapeContext& context) {
  value.expect_object({"type", "basis", "file", "control_points", "curve_sizes", "material",
                       "two_sided", "transform"},
                      "a \"curves\" shape");
  Shape shape;
  shape.kind = Shape::Kind::curves;
  shape.origin = value.path();
  shape.curve_basis = parse_basis(value);
  if (value.has("file") == value.has("control_points")) {
    value.fail("a \"curves\" shape gives either \"file\" or \"control_points\"");
  }
  if (std::optional<JsonValue> file = value.find("file")) {
    if (value.has("curve_sizes")) value.at("curve_sizes").fail("only with \"control_points\"");
    std::string path = check_bundle_path(file->string(), file->path());
    try {
      CurveFile curves = parse_curve_file(context.reader(path), path, shape.curve_basis);
      shape.control_points = std::move(curves.control_points);
      shape.curve_sizes = std::move(curves.curve_sizes);
    } catch (const SceneError& e) {
      file->fail(e.what());
    }
    std::vector<std::string>& files = context.referenced_files;
    if (std::find(files.begin(), files.end(), path) == files.end()) files.push_back(path);
  } else {
    read_inline(value, shape);
  }
  if (std::optional<JsonValue> t = value.find("transform")) {
    place_curve_points(shape.control_points, parse_transform(*t), t->path());
  }
  std::optional<JsonValue> material = value.find("material");
  if (!material) {
    throw SceneError(value.child_path("material") + ": required (curves cannot emit light)");
  }
  std::optional<uint32_t> index = context.materials.find_declared(material->string());
  if (!index) material->fail("unknown material \"" + printable(material->string()) + "\"");
  const bool two_sided = value.boolean_or("two_sided", false);
  shape.material = two_sided ? context.materials.two_sided(*index) : *index;
  return shape;
}

}  // namespace tessera
