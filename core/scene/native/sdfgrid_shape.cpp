#include "scene/native/sdfgrid_shape.h"

#include <algorithm>
#include <cmath>

#include "scene/native/transform_parser.h"
#include "scene/scene_error.h"
#include "scene/bundle_path.h"

namespace tessera {
namespace {

/// Empty when the grid is usable; otherwise what is wrong with it.
std::string grid_problem(glm::u32vec3 r, const std::vector<float>& values) {
  if (r.x < 2 || r.y < 2 || r.z < 2) {
    return "an SDF grid needs at least 2 samples along each axis (got " + std::to_string(r.x) + " x " +
           std::to_string(r.y) + " x " + std::to_string(r.z) + ")";
  }
  if (uint64_t(r.x) * r.y * r.z != values.size()) {
    return std::to_string(values.size()) + " values for a grid of " + std::to_string(r.x) + " x " +
           std::to_string(r.y) + " x " + std::to_string(r.z);
  }
  for (size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) return "value " + std::to_string(i) + " is not finite";
  }
  if (sdf_surface_voxel_count(r, values) == 0) {
    return "no voxel of the SDF grid holds the surface (its values never change sign and none is "
           "0); Mitsuba refuses such a grid too (\"SDFGrid should at least have one non-empty "
           "voxel\")";
  }
  return {};
}

SdfNormals parse_normals(const JsonValue& value) {
  std::optional<JsonValue> normals = value.find("normals");
  if (!normals) return SdfNormals::smooth;
  const std::string& name = normals->string();
  if (name == "smooth") return SdfNormals::smooth;
  if (name == "analytic") return SdfNormals::analytic;
  normals->fail("unknown normals \"" + printable(name) + "\" (expected smooth or analytic)");
}

void read_inline(const JsonValue& value, Shape& shape) {
  JsonValue resolution = value.at("resolution");
  std::vector<JsonValue> n = resolution.elements(3);
  for (int a = 0; a < 3; ++a) shape.sdf_resolution[a] = uint32_t(n[a].integer(2, 1 << 20));
  const uint64_t count = uint64_t(shape.sdf_resolution.x) * shape.sdf_resolution.y * shape.sdf_resolution.z;
  if (count > kMaxVolumeGridValues) {
    resolution.fail("the grid has " + std::to_string(count) + " values, more than the " +
                    std::to_string(kMaxVolumeGridValues) + " allowed");
  }
  JsonValue values = value.at("values");
  for (const JsonValue& v : values.elements()) {
    const double x = v.number();
    const auto f = float(x);
    if (!std::isfinite(f)) v.fail("a value must be finite as a 32-bit float (got " + format_number(x) + ")");
    shape.sdf_values.push_back(f);
  }
  const std::string problem = grid_problem(shape.sdf_resolution, shape.sdf_values);
  if (!problem.empty()) values.fail(problem);
}

}  // namespace

uint64_t sdf_surface_voxel_count(glm::u32vec3 r, const std::vector<float>& values) {
  if (r.x < 2 || r.y < 2 || r.z < 2 || uint64_t(r.x) * r.y * r.z != values.size()) return 0;
  uint64_t count = 0;
  for (uint32_t z = 0; z + 1 < r.z; ++z) {
    for (uint32_t y = 0; y + 1 < r.y; ++y) {
      for (uint32_t x = 0; x + 1 < r.x; ++x) {
        bool nonneg = false, nonpos = false;
        for (uint32_t c = 0; c < 8; ++c) {
          const size_t i = ((size_t(z + (c >> 2)) * r.y + y + ((c >> 1) & 1)) * r.x) + x + (c & 1);
          nonneg |= values[i] >= 0;
          nonpos |= values[i] <= 0;
        }
        count += nonneg && nonpos;
      }
    }
  }
  return count;
}

void set_sdf_grid(Shape& shape, VolumeGridFile grid, const std::string& path) {
  if (grid.channels != 1) {
    throw SceneError(path + ": an SDF grid has 1 channel, this file has " + std::to_string(grid.channels));
  }
  const std::string problem = grid_problem(grid.resolution, grid.values);
  if (!problem.empty()) throw SceneError(path + ": " + problem);
  shape.kind = Shape::Kind::sdfgrid;
  shape.sdf_resolution = grid.resolution;
  shape.sdf_values = std::move(grid.values);
  shape.sdf_file = path;
}

Shape parse_sdfgrid_shape(const JsonValue& value, ShapeContext& context) {
  value.expect_object({"type", "file", "resolution", "values", "normals", "material", "two_sided", "transform"},
                      "an \"sdfgrid\" shape");
  Shape shape;
  shape.kind = Shape::Kind::sdfgrid;
  shape.origin = value.path();
  if (value.has("file") == value.has("values")) {
    value.fail("an \"sdfgrid\" shape gives either \"file\" or \"resolution\" and \"values\"");
  }
  if (std::optional<JsonValue> file = value.find("file")) {
    if (value.has("resolution")) value.at("resolution").fail("only with \"values\"");
    std::string path = check_bundle_path(file->string(), file->path());
    try {
      set_sdf_grid(shape, parse_volume_grid_file(context.reader(path), path), path);
    } catch (const SceneError& e) {
      file->fail(e.what());
    }
    std::vector<std::string>& files = context.referenced_files;
    if (std::find(files.begin(), files.end(), path) == files.end()) files.push_back(path);
  } else {
    read_inline(value, shape);
  }
  shape.sdf_normals = parse_normals(value);
  if (std::optional<JsonValue> t = value.find("transform")) {
    const Transform to_world = parse_transform(*t);
    const double det = to_world.determinant();
    if (!(std::abs(det) > 0) || !std::isfinite(det)) {
      t->fail("an SDF grid's transform must be invertible (determinant " + format_number(det) + ")");
    }
    shape.to_world = to_world.matrix();
  }
  std::optional<JsonValue> material = value.find("material");
  if (!material) {
    throw SceneError(value.child_path("material") + ": required (SDF grids cannot emit light)");
  }
  std::optional<uint32_t> index = context.materials.find_declared(material->string());
  if (!index) material->fail("unknown material \"" + printable(material->string()) + "\"");
  const bool two_sided = value.boolean_or("two_sided", false);
  shape.material = two_sided ? context.materials.two_sided(*index) : *index;
  return shape;
}

}  // namespace tessera
