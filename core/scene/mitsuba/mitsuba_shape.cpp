#include "scene/mitsuba/mitsuba_shape.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "scene/native/json_value.h"
#include "scene/mesh/mesh_file.h"
#include "scene/mitsuba/mitsuba_plugin.h"
#include "scene/mitsuba/mitsuba_shape_geometry.h"
#include "scene/mitsuba/mitsuba_vertex_normals.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

constexpr const char* kSupported =
    "Tessera supports obj, ply, rectangle, cube, sphere and disk; convert other geometry to PLY";

/// The geometry of a mesh file, in object space.
TriangleMesh load_file(MitsubaPlugin& plugin, MitsubaShapeContext& context, bool face_normals,
                       size_t& dropped) {
  std::optional<std::string> filename = plugin.take_string("filename");
  if (!filename) fail_at(plugin.element(), "missing <string name=\"filename\">");
  const MitsubaElement& where = *plugin.property("filename");
  std::string relative = check_bundle_path(*filename, where.where());
  std::string path = where.folder + relative;  // relative to the XML file that names it
  MeshFileOptions options;
  options.use_file_materials = false;  // Mitsuba reads no MTL files
  options.face_normals = face_normals;
  std::vector<std::string> files_read;
  std::vector<MeshPart> parts;
  try {
    parts = load_mesh_file(path, context.reader, options, files_read);
  } catch (const SceneError& e) {
    fail_at(where, e.what());
  }
  for (const std::string& f : files_read) {
    std::vector<std::string>& files = context.referenced_files;
    if (std::find(files.begin(), files.end(), f) == files.end()) files.push_back(f);
  }
  if (parts.size() != 1) fail_at(where, "the file gives no geometry");
  dropped = parts.front().dropped_faces;
  return std::move(parts.front().mesh);
}

/// Puts a mesh in world space the way Mitsuba does, in the form the native format reads back
/// exactly (see stable_unit_vector).
void place_mesh(TriangleMesh& mesh, const Transform& to_world, bool flip, bool from_file,
                bool face_normals, size_t& dropped, const MitsubaElement& shape) {
  transform_mesh(mesh, to_world);
  if (flip) flip_mesh(mesh);
  if (!positions_finite(mesh)) fail_at(shape, "a vertex overflows after to_world");
  if (from_file) {
    // Normals first: Mitsuba keeps nearly degenerate faces, and they weigh in at their vertices.
    if (mesh.normals.empty() && !face_normals) compute_mitsuba_vertex_normals(mesh);
    dropped += drop_degenerate_triangles(mesh);
    if (mesh.indices.empty()) {
      fail_at(shape, "no triangles (" + std::to_string(dropped) + " degenerate faces dropped)");
    }
  } else if (first_degenerate_triangle(mesh)) {
    fail_at(shape, "to_world makes the shape degenerate");
  }
  // The native parser maps positions through an identity transform, which turns -0 into +0;
  // doing it here makes that a no-op.
  const Transform identity;
  for (glm::dvec3& p : mesh.positions) p = identity.point(p);
  for (glm::dvec3& n : mesh.normals) n = stable_unit_vector(n);
}

void place_sphere(Shape& shape, MitsubaPlugin& plugin, const Transform& to_world) {
  glm::dvec3 center = plugin.take_point("center").value_or(glm::dvec3(0));
  double radius = plugin.take_float("radius").value_or(1.0);
  if (!(radius > 0)) {
    fail_at(*plugin.property("radius"), "must be > 0 (got " + format_number(radius) + ")");
  }
  std::optional<double> scale = to_world.similarity_scale();
  if (!scale) {
    fail_at(*plugin.property("to_world"),
            "a sphere's to_world must be a similarity (rotation, uniform scale, translation): "
            "Tessera keeps spheres exact");
  }
  shape.kind = Shape::Kind::sphere;
  shape.center = Transform().point(to_world.point(center));
  shape.radius = radius * *scale;
  glm::dvec3 c = shape.center;
  if (!std::isfinite(c.x + c.y + c.z) || !std::isfinite(shape.radius) || !(shape.radius > 0)) {
    fail_at(plugin.element(), "the sphere does not stay finite after to_world");
  }
}

uint32_t read_material(MitsubaPlugin& plugin, MitsubaShapeContext& context) {
  std::vector<MitsubaObject> bsdfs = plugin.take_objects("bsdf");
  if (bsdfs.size() > 1) fail_at(*bsdfs[1].written, "a shape has at most one BSDF");
  if (bsdfs.empty()) return context.materials.default_material();
  return context.materials.of(*bsdfs.front().element);
}

/// The radiance of the shape's area emitter, or zero without one.
glm::dvec3 read_emitter(MitsubaPlugin& plugin, const MitsubaIds& ids) {
  std::vector<MitsubaObject> emitters = plugin.take_objects("emitter");
  if (emitters.empty()) return glm::dvec3(0);
  if (emitters.size() > 1) fail_at(*emitters[1].written, "a shape has at most one emitter");
  MitsubaPlugin emitter(*emitters.front().element, ids);
  if (emitter.type() != "area") {
    fail_at(emitter.element(),
            "a shape's emitter must be \"area\" (Tessera's lights are "
            "emitting shapes)");
  }
  std::optional<glm::dvec3> radiance = emitter.take_color("radiance");
  if (!radiance) {
    fail_at(emitter.element(),
            "give <rgb name=\"radiance\" .../> (Mitsuba's default is a D65 spectrum, which "
            "Tessera does not model)");
  }
  for (int i = 0; i < 3; ++i) {
    if (!((*radiance)[i] >= 0)) {
      fail_at(*emitter.property("radiance"),
              "each channel must be >= 0 (got " + format_number((*radiance)[i]) + ")");
    }
  }
  emitter.ignore("sampling_weight");  // how often it is sampled: noise only
  emitter.finish();
  return *radiance;
}

double area_of(const Shape& shape) {
  if (shape.kind == Shape::Kind::sphere) {
    return 4 * std::numbers::pi * shape.radius * shape.radius;
  }
  double area = 0;
  for (const glm::u32vec3& t : shape.indices) {
    area += triangle_area(shape.positions[t.x], shape.positions[t.y], shape.positions[t.z]);
  }
  return area;
}

}  // namespace

Shape read_mitsuba_shape(const MitsubaElement& element, MitsubaShapeContext& context) {
  MitsubaPlugin plugin(element, context.ids);
  const std::string& type = plugin.type();
  bool is_file = type == "obj" || type == "ply";
  if (!is_file && type != "rectangle" && type != "cube" && type != "disk" && type != "sphere") {
    fail_at(element, std::string("unsupported shape (") + kSupported + ")");
  }
  Transform to_world = plugin.take_transform("to_world").value_or(Transform());
  bool flip = plugin.take_boolean("flip_normals").value_or(false);
  Shape shape;
  shape.origin = element.where();
  shape.flip_normals = flip;
  if (type == "sphere") {
    place_sphere(shape, plugin, to_world);
  } else {
    TriangleMesh mesh;
    size_t dropped = 0;
    bool face_normals = false;
    if (is_file) {
      face_normals = plugin.take_boolean("face_normals").value_or(false);
      if (type == "obj") plugin.ignore("flip_tex_coords");  // texture coordinates: unused
      mesh = load_file(plugin, context, face_normals, dropped);
    } else {
      mesh = type == "rectangle" ? mitsuba_rectangle()
             : type == "cube"    ? mitsuba_cube()
                                 : mitsuba_disk();
    }
    place_mesh(mesh, to_world, flip, is_file, face_normals, dropped, element);
    shape.positions = std::move(mesh.positions);
    shape.normals = std::move(mesh.normals);
    shape.indices = std::move(mesh.indices);
    shape.dropped_triangles = dropped;
  }
  shape.material = read_material(plugin, context);
  shape.emission = read_emitter(plugin, context.ids);
  if (shape.is_emitter()) {
    double area = area_of(shape);
    if (!(area > 0) || !std::isfinite(area)) {
      fail_at(element,
              "a light must have a positive, finite area (got " + format_number(area) + ")");
    }
  }
  plugin.finish();
  return shape;
}

}  // namespace tessera
