#include "scene/native/shape_parser.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "scene/bundle_path.h"
#include "scene/mesh/mesh_file.h"
#include "scene/native/curve_shape.h"
#include "scene/native/sdfgrid_shape.h"
#include "scene/scene_error.h"
#include "scene/native/shape_builders.h"
#include "scene/native/shape_light.h"
#include "scene/native/transform_parser.h"

namespace tessera {
namespace {

/// The geometry of a shape object, or of one material group of its mesh file.
struct Part {
  bool is_sphere = false;
  SphereGeometry sphere;
  TriangleMesh mesh;
  bool from_file = false;
  std::string label;
  std::optional<Material> file_material;
  glm::dvec3 file_emission{0};
  size_t dropped = 0;
};

/// The keys a shape object of `type` accepts; empty for an unknown type.
std::vector<std::string_view> keys_of(std::string_view type) {
  std::vector<std::string_view> keys = {"type",      "material",     "emission", "power",
                                        "two_sided", "flip_normals", "transform",
                                        "interior",  "exterior"};
  if (type == "quad" || type == "tetrahedron") {
    keys.push_back("vertices");
  } else if (type == "sphere") {
    keys.insert(keys.end(), {"center", "radius", "frame"});
  } else if (type == "triangles") {
    keys.insert(keys.end(), {"vertices", "indices", "normals", "uvs", "attributes"});
  } else if (type == "box") {
    keys.insert(keys.end(), {"min", "max"});
  } else if (type == "mesh") {
    keys.insert(keys.end(), {"file", "face_normals", "shape_index"});
  } else {
    return {};
  }
  return keys;
}

void add_referenced(std::vector<std::string>& files, const std::string& path) {
  if (std::find(files.begin(), files.end(), path) == files.end()) files.push_back(path);
}

std::vector<Part> load_mesh_parts(const JsonValue& value, bool use_file_materials,
                                  ShapeContext& context) {
  JsonValue file = value.at("file");
  std::string path = check_bundle_path(file.string(), file.path());
  MeshFileOptions options{use_file_materials, value.boolean_or("face_normals", false)};
  if (std::optional<JsonValue> index = value.find("shape_index")) {
    options.shape_index = static_cast<int>(index->integer(0, INT32_MAX));
  }
  std::vector<std::string> files_read;
  std::vector<MeshPart> mesh_parts;
  try {
    mesh_parts = load_mesh_file(path, context.reader, options, files_read);
  } catch (const SceneError& e) {
    file.fail(e.what());
  }
  for (const std::string& f : files_read) add_referenced(context.referenced_files, f);
  std::vector<Part> parts;
  for (MeshPart& m : mesh_parts) {
    Part part;
    part.mesh = std::move(m.mesh);
    part.from_file = true;
    part.label = std::move(m.label);
    part.file_material = std::move(m.material);
    part.file_emission = m.emission;
    part.dropped = m.dropped_faces;
    parts.push_back(std::move(part));
  }
  return parts;
}

/// "attributes": {"vertex_<name>": rows, "face_<name>": rows}, a row a number (1 channel) or
/// [r, g, b] (3 channels), one per vertex or per triangle.
std::vector<MeshAttribute> parse_mesh_attributes(const JsonValue& value, const TriangleMesh& mesh) {
  std::vector<MeshAttribute> attributes;
  for (const auto& [name, rows] : value.members()) {
    MeshAttribute a;
    a.name = name;
    std::vector<JsonValue> items = rows.elements();
    a.channels = !items.empty() && items[0].json().is_array() ? 3 : 1;
    for (const JsonValue& item : items) {
      if (a.channels == 1) {
        a.values.push_back(float(item.number()));
      } else {
        for (const JsonValue& c : item.elements(3)) a.values.push_back(float(c.number()));
      }
    }
    attributes.push_back(std::move(a));
    std::string problem =
        mesh_attributes_problem(attributes, mesh.positions.size(), mesh.indices.size());
    if (!problem.empty()) rows.fail(problem);
  }
  return attributes;
}

std::vector<Part> build_parts(const JsonValue& value, std::string_view type,
                              bool use_file_materials, ShapeContext& context) {
  if (type == "mesh") return load_mesh_parts(value, use_file_materials, context);
  Part part;
  if (type == "sphere") {
    part.is_sphere = true;
    part.sphere = build_sphere(value);
  } else if (type == "quad") {
    part.mesh = build_quad(value);
  } else if (type == "triangles") {
    part.mesh = build_triangles(value);
    if (std::optional<JsonValue> attributes = value.find("attributes")) {
      part.mesh.attributes = parse_mesh_attributes(*attributes, part.mesh);
    }
  } else if (type == "box") {
    part.mesh = build_box(value);
  } else {
    part.mesh = build_tetrahedron(value);
  }
  std::vector<Part> parts;
  parts.push_back(std::move(part));
  return parts;
}

/// Spheres stay spheres: only similarities keep them so.
void place_sphere(Part& part, const Transform& transform, const JsonValue& value) {
  std::optional<double> scale = transform.similarity_scale();
  if (!scale) {
    throw SceneError(value.child_path("transform") +
                     ": a sphere's transform must be a similarity (rotation, uniform scale, "
                     "translation)");
  }
  part.sphere.center = transform.point(part.sphere.center);
  part.sphere.radius *= *scale;
  if (transform.matrix() != glm::dmat4(1.0)) {
    part.sphere.frame = glm::dmat3(transform.matrix()) * (1 / *scale) * part.sphere.frame;
  }
  glm::dvec3 c = part.sphere.center;
  if (!std::isfinite(c.x + c.y + c.z) || !std::isfinite(part.sphere.radius) ||
      !(part.sphere.radius > 0)) {
    throw SceneError(value.child_path("transform") + ": the sphere does not stay finite");
  }
}

/// Degenerate triangles: dropped and counted in mesh files (scans have some), an error in
/// geometry the scene spells out.
void check_degenerate(Part& part, const JsonValue& value, std::string_view type) {
  if (part.from_file) {
    part.dropped += drop_degenerate_triangles(part.mesh);
    return;
  }
  std::optional<size_t> bad = first_degenerate_triangle(part.mesh);
  if (!bad) return;
  if (type == "triangles") {
    throw SceneError(value.child_path("indices") + "[" + std::to_string(*bad) +
                     "]: degenerate triangle (zero area)");
  }
  throw SceneError(value.child_path("transform") + ": makes the shape degenerate");
}

void place_mesh(Part& part, const Transform& transform, bool flip, const JsonValue& value,
                std::string_view type) {
  transform_mesh(part.mesh, transform);
  if (flip) flip_mesh(part.mesh);
  if (!positions_finite(part.mesh)) {
    throw SceneError(value.child_path("transform") + ": a vertex overflows after the transform");
  }
  check_degenerate(part, value, type);
}

/// Removes parts of a mesh file left without triangles; an error when none is left.
void drop_empty_parts(std::vector<Part>& parts, const JsonValue& value) {
  size_t dropped = 0;
  for (const Part& part : parts) {
    if (!part.is_sphere && part.mesh.indices.empty()) dropped += part.dropped;
  }
  std::erase_if(parts, [](const Part& p) { return !p.is_sphere && p.mesh.indices.empty(); });
  if (parts.empty()) {
    std::string file = value.has("file") ? value.at("file").string() + ": " : "";
    throw SceneError(value.child_path("file") + ": " + file + "no triangles (" +
                     std::to_string(dropped) + " degenerate faces dropped)");
  }
  parts.front().dropped += dropped;
}

double part_area(const Part& part) {
  if (part.is_sphere) return 4 * std::numbers::pi * part.sphere.radius * part.sphere.radius;
  return mesh_area(part.mesh);
}

std::optional<uint32_t> declared_material(const JsonValue& value, MaterialTable& table) {
  std::optional<JsonValue> material = value.find("material");
  if (!material) return std::nullopt;
  const std::string& name = material->string();
  std::optional<uint32_t> index = table.find_declared(name);
  if (!index) material->fail("unknown material \"" + printable(name) + "\"");
  return index;
}

uint32_t part_material(const Part& part, std::optional<uint32_t> declared, bool is_light,
                       const JsonValue& value, MaterialTable& table) {
  if (declared) return *declared;
  if (part.file_material) return table.derive(*part.file_material);
  if (is_light) return table.black();
  if (part.from_file) {
    throw SceneError(value.child_path("material") +
                     ": required (the mesh file gives no material to some of its faces)");
  }
  throw SceneError(value.child_path("material") + ": required (only lights may omit it)");
}

Shape make_shape(Part& part, const JsonValue& value, bool flip, bool several) {
  Shape shape;
  shape.kind = part.is_sphere ? Shape::Kind::sphere : Shape::Kind::triangles;
  shape.positions = std::move(part.mesh.positions);
  shape.normals = std::move(part.mesh.normals);
  shape.uvs = std::move(part.mesh.uvs);
  shape.attributes = std::move(part.mesh.attributes);
  shape.indices = std::move(part.mesh.indices);
  shape.center = part.sphere.center;
  shape.radius = part.sphere.radius;
  shape.frame = part.sphere.frame;
  shape.flip_normals = flip;
  shape.dropped_triangles = part.dropped;
  shape.origin = value.path();
  if (several || !part.label.empty()) {
    shape.origin += " (" + (part.label.empty() ? "no material" : printable(part.label)) + ")";
  }
  return shape;
}

Shape parse_instance(const JsonValue& value, const ShapeContext& context) {
  value.expect_object({"type", "group", "transform"}, "an \"instance\" shape");
  JsonValue group = value.at("group");
  if (!context.groups) value.at("type").fail("groups cannot hold instances");
  auto it = context.groups->find(group.string());
  if (it == context.groups->end()) {
    group.fail("unknown group \"" + printable(group.string()) + "\"");
  }
  Shape shape;
  shape.kind = Shape::Kind::instance;
  shape.group = it->second;
  if (std::optional<JsonValue> t = value.find("transform")) {
    shape.to_world = parse_transform(*t).matrix();
  }
  shape.origin = value.path();
  return shape;
}

}  // namespace

void parse_shape(const JsonValue& value, ShapeContext& context, std::vector<Shape>& shapes) {
  JsonValue type_value = value.at("type");
  const std::string& type = type_value.string();
  if (type == "instance") return shapes.push_back(parse_instance(value, context));
  if (type == "curves") return shapes.push_back(parse_curve_shape(value, context));
  if (type == "sdfgrid") return shapes.push_back(parse_sdfgrid_shape(value, context));
  std::vector<std::string_view> keys = keys_of(type);
  if (keys.empty()) {
    type_value.fail("unknown shape type \"" + printable(type) +
                    "\" (expected quad, sphere, triangles, box, tetrahedron, mesh, curves, sdfgrid or instance)");
  }
  value.expect_object(keys, "a \"" + type + "\" shape");
  LightSpec light = parse_light(value, context.textures);
  if (light.emission_texture >= 0 && light.power_w) {
    value.at("power").fail("a textured emission cannot be given as power");
  }
  std::optional<uint32_t> declared = declared_material(value, context.materials);
  bool two_sided = value.boolean_or("two_sided", false);
  bool flip = value.boolean_or("flip_normals", false);
  Transform transform;
  if (std::optional<JsonValue> t = value.find("transform")) transform = parse_transform(*t);

  int32_t media[2] = {-1, -1};
  for (int side = 0; side < 2; ++side) {
    if (std::optional<JsonValue> medium = value.find(side == 0 ? "interior" : "exterior")) {
      if (!context.media) medium->fail("shapes in a group cannot bound a medium");
      media[side] = medium_index(*medium, *context.media);
    }
  }

  std::vector<Part> parts = build_parts(value, type, !declared.has_value(), context);
  for (Part& part : parts) {
    if (part.is_sphere) {
      place_sphere(part, transform, value);
    } else {
      place_mesh(part, transform, flip, value, type);
    }
  }
  if (type == "mesh") drop_empty_parts(parts, value);
  double area = 0;
  for (const Part& part : parts) area += part_area(part);
  glm::dvec3 radiance = light.given ? light_radiance(light, area, two_sided, value) : glm::dvec3(0);

  for (Part& part : parts) {
    uint32_t material = part_material(part, declared, light.given, value, context.materials);
    Shape shape = make_shape(part, value, flip, parts.size() > 1);
    shape.material = two_sided ? context.materials.two_sided(material) : material;
    shape.emission = light.given ? radiance : part.file_emission;
    shape.emission_texture = light.emission_texture;
    shape.two_sided_emission = two_sided && shape.is_emitter();
    shape.interior = media[0];
    shape.exterior = media[1];
    shapes.push_back(std::move(shape));
  }
}

}  // namespace tessera
