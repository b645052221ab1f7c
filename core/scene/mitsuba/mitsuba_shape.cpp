#include "scene/mitsuba/mitsuba_shape.h"

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <limits>
#include <numbers>

#include "scene/message_text.h"
#include "scene/mesh/curve_file.h"
#include "scene/mesh/mesh_file.h"
#include "scene/native/curve_shape.h"
#include "scene/native/sdfgrid_shape.h"
#include "scene/volume_grid_file.h"
#include "scene/mitsuba/mitsuba_emitter.h"
#include "scene/mitsuba/mitsuba_plugin.h"
#include "scene/mitsuba/mitsuba_shape_geometry.h"
#include "scene/mitsuba/mitsuba_vertex_normals.h"
#include "scene/scene_error.h"

#include "scene/mesh/serialized_loader.h"

namespace tessera {
namespace {

constexpr const char* kSupported =
    "Tessera supports obj, ply, serialized, rectangle, cube, sphere, disk, cylinder, "
    "linearcurve, bsplinecurve, sdfgrid, shapegroup and instance; convert other geometry to PLY";

/// The geometry of a mesh file, in object space.
TriangleMesh load_file(MitsubaPlugin& plugin, MitsubaShapeContext& context, bool face_normals,
                       size_t& dropped) {
  std::optional<std::string> filename = plugin.take_string("filename");
  if (!filename) fail_at(plugin.element(), "missing <string name=\"filename\">");
  const MitsubaElement& where = *plugin.property("filename");
  std::string path = context.files.resolve(where, *filename);
  MeshFileOptions options;
  options.use_file_materials = false;  // Mitsuba reads no MTL files
  options.face_normals = face_normals;
  std::vector<std::string> files_read;
  std::vector<MeshPart> parts;
  try {
    parts = load_mesh_file(path, context.files.reader(), options, files_read);
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

/// Shape `shape_index` of a Mitsuba .serialized file, in object space.
TriangleMesh load_serialized(MitsubaPlugin& plugin, MitsubaShapeContext& context,
                             bool face_normals) {
  std::optional<std::string> filename = plugin.take_string("filename");
  if (!filename) fail_at(plugin.element(), "missing <string name=\"filename\">");
  const MitsubaElement& where = *plugin.property("filename");
  std::string path = context.files.resolve(where, *filename);
  int64_t index = plugin.take_integer("shape_index").value_or(0);
  if (index < 0 || index > std::numeric_limits<int>::max()) {
    fail_at(*plugin.property("shape_index"), "must be >= 0 (got " + std::to_string(index) + ")");
  }
  SerializedMesh mesh;
  try {
    mesh = load_serialized_mesh(context.files.read(path), path, int(index), !face_normals);
  } catch (const SceneError& e) {
    fail_at(where, e.what());
  }
  std::vector<std::string>& files = context.referenced_files;
  if (std::find(files.begin(), files.end(), path) == files.end()) files.push_back(path);
  return std::move(mesh.mesh);
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
    // A file whose faces are all degenerate leaves an empty mesh, which Mitsuba loads and no
    // ray hits: the scene leaves it out (mitsuba_shape_is_empty), a light of it is refused.
    dropped += drop_degenerate_triangles(mesh);
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
  shape.frame = glm::dmat3(to_world.matrix()) / *scale;
  glm::dvec3 c = shape.center;
  if (!std::isfinite(c.x + c.y + c.z) || !std::isfinite(shape.radius) || !(shape.radius > 0)) {
    fail_at(plugin.element(), "the sphere does not stay finite after to_world");
  }
}

/// p0, p1 and radius of a cylinder as the transform from its own space.
Transform cylinder_placement(MitsubaPlugin& plugin) {
  glm::dvec3 p0 = plugin.take_point("p0").value_or(glm::dvec3(0));
  glm::dvec3 p1 = plugin.take_point("p1").value_or(glm::dvec3(0, 0, 1));
  double radius = plugin.take_float("radius").value_or(1.0);
  if (!(radius > 0)) {
    fail_at(*plugin.property("radius"), "must be > 0 (got " + format_number(radius) + ")");
  }
  if (p0 == p1) fail_at(plugin.element(), "p0 and p1 must differ");
  glm::dmat4 m = mitsuba_cylinder_placement(p0, p1, radius);
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      if (!std::isfinite(m[c][r])) fail_at(plugin.element(), "the cylinder is not finite");
    }
  }
  return Transform(m);
}

/// `emitter`: the shape has an area emitter (then Mitsuba's default BSDF is black).
uint32_t read_material(MitsubaPlugin& plugin, MitsubaShapeContext& context, bool emitter) {
  std::vector<MitsubaObject> bsdfs = plugin.take_objects("bsdf");
  if (bsdfs.size() > 1) fail_at(*bsdfs[1].written, "a shape has at most one BSDF");
  if (bsdfs.empty()) return context.materials.default_material(emitter);
  return context.materials.of(*bsdfs.front().element);
}

/// A point, spot, directional or projector emitter written inside a shape. Mitsuba's scene
/// (scene.cpp) adds a shape's emitter to its emitters whatever the type; such a light keeps its
/// own to_world (it does not move with the shape), a hit on the shape finds no emission (their
/// eval() is 0), and the shape's default BSDF is black as for any shape with an emitter
/// (shape.cpp). So it is a light of the scene like one written at the top. An environment
/// emitter would join the sampled emitters without being the scene's environment (escaping
/// rays would not see it): refused.
void read_nested_light(const MitsubaObject& emitter, MitsubaShapeContext& context) {
  const MitsubaElement& element = *emitter.element;
  const std::string* type = element.attribute("type");
  if (type && (*type == "constant" || *type == "envmap")) {
    fail_at(*emitter.written,
            "a " + *type +
                " emitter inside a shape: Mitsuba samples it as a light but escaping rays do "
                "not see it (it is not the scene's environment), which Tessera does not render; "
                "put it at the top of the scene");
  }
  if (emitter.written->tag == "ref") {
    // Declared at the top, it is a light of the scene there already; Mitsuba would list it
    // twice among its emitters.
    fail_at(*emitter.written,
            "a " + std::string(type ? *type : "non-area") +
                " emitter named by <ref> inside a shape: write it inside the shape or at the top "
                "of the scene, not both");
  }
  context.lights.push_back(read_mitsuba_light(element, context.ids, context.files,
                                              context.referenced_files, context.textures));
  std::fprintf(stderr,
               "note: %s: line %d: the %s emitter inside this shape is a light of the scene, as "
               "in Mitsuba: it keeps its own to_world, the shape does not glow, and the shape's "
               "default BSDF is black\n",
               element.file.c_str(), element.line, type ? type->c_str() : "?");
}

/// The shape's emitter, if any; whether it has one. An area emitter makes the shape glow;
/// another kind is a light of the scene (read_nested_light).
bool read_emitter(MitsubaPlugin& plugin, MitsubaShapeContext& context, Shape& shape) {
  std::vector<MitsubaObject> emitters = plugin.take_objects("emitter");
  if (emitters.empty()) return false;
  if (emitters.size() > 1) fail_at(*emitters[1].written, "a shape has at most one emitter");
  const std::string* type = emitters.front().element->attribute("type");
  if (type && *type != "area") {
    read_nested_light(emitters.front(), context);
    return true;
  }
  MitsubaAreaEmission emission =
      read_mitsuba_area_emitter(*emitters.front().element, context.ids, context.textures);
  shape.emission = emission.radiance;
  shape.emission_texture = emission.texture;
  return true;
}

/// Media on either side of a curve or SDF grid: refused (Tessera's media are bounded by
/// triangles and spheres).
void refuse_media(MitsubaPlugin& plugin) {
  for (const MitsubaObject& medium : plugin.take_objects("medium")) {
    fail_at(*medium.written,
            "only meshes and spheres bound participating media in Tessera (not curves or SDF grids)");
  }
}

/// A shape's interior and exterior media: <medium name="interior|exterior"> or a <ref> so named.
void read_media(MitsubaPlugin& plugin, MitsubaShapeContext& context, Shape& shape) {
  for (const MitsubaObject& medium : plugin.take_objects("medium")) {
    const std::string* name = medium.written->attribute("name");
    int32_t* side = name && *name == "interior"   ? &shape.interior
                    : name && *name == "exterior" ? &shape.exterior
                                                  : nullptr;
    if (!side) {
      fail_at(*medium.written, "a shape's medium is named \"interior\" or \"exterior\" (got " +
                                   (name ? "\"" + *name + "\"" : std::string("no name")) + ")");
    }
    if (*side >= 0) fail_at(*medium.written, "a second " + *name + " medium");
    *side = context.media.of(*medium.element);
  }
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

/// linearcurve and bsplinecurve: the curve file in world space (to_world moves the control
/// points and leaves their radii as they are, as in Mitsuba).
Shape read_curves(MitsubaPlugin& plugin, MitsubaShapeContext& context) {
  Shape shape;
  shape.kind = Shape::Kind::curves;
  shape.origin = plugin.element().where();
  shape.curve_basis = plugin.type() == "linearcurve" ? CurveBasis::linear : CurveBasis::bspline;
  std::optional<std::string> filename = plugin.take_string("filename");
  if (!filename) fail_at(plugin.element(), "missing <string name=\"filename\">");
  const MitsubaElement& where = *plugin.property("filename");
  std::string path = context.files.resolve(where, *filename);
  CurveFile curves;
  try {
    curves = parse_curve_file(context.files.read(path), path, shape.curve_basis);
  } catch (const SceneError& e) {
    fail_at(where, e.what());
  }
  std::vector<std::string>& files = context.referenced_files;
  if (std::find(files.begin(), files.end(), path) == files.end()) files.push_back(path);
  shape.control_points = std::move(curves.control_points);
  shape.curve_sizes = std::move(curves.curve_sizes);
  if (std::optional<Transform> to_world = plugin.take_transform("to_world")) {
    try {
      place_curve_points(shape.control_points, *to_world, "to_world");
    } catch (const SceneError& e) {
      fail_at(*plugin.property("to_world"), e.what());
    }
  }
  if (!plugin.take_objects("emitter").empty()) {
    fail_at(plugin.element(), "curves cannot emit light in Tessera");
  }
  shape.material = read_material(plugin, context, false);
  refuse_media(plugin);
  plugin.finish();
  return shape;
}

/// sdfgrid: the .vol file's values over [0, 1]^3 placed by to_world (any invertible affine
/// map: Mitsuba warns about rotations and renders them). Mitsuba reads no flip_normals here
/// (it refuses the property as unreferenced) and its sdfgrid cannot be an area emitter.
Shape read_sdfgrid(MitsubaPlugin& plugin, MitsubaShapeContext& context) {
  Shape shape;
  shape.kind = Shape::Kind::sdfgrid;
  shape.origin = plugin.element().where();
  std::optional<std::string> normals = plugin.take_string("normals");
  if (normals && *normals == "analytic") {
    shape.sdf_normals = SdfNormals::analytic;
  } else if (normals && *normals != "smooth") {
    fail_at(*plugin.property("normals"),
            "unknown normals \"" + printable(*normals) + "\" (expected smooth or analytic)");
  }
  std::optional<std::string> filename = plugin.take_string("filename");
  if (!filename) {
    fail_at(plugin.element(), "missing <string name=\"filename\"> (Tessera reads SDF grids from .vol files)");
  }
  const MitsubaElement& where = *plugin.property("filename");
  std::string path = context.files.resolve(where, *filename);
  try {
    set_sdf_grid(shape, parse_volume_grid_file(context.files.read(path), path), path);
  } catch (const SceneError& e) {
    fail_at(where, e.what());
  }
  std::vector<std::string>& files = context.referenced_files;
  if (std::find(files.begin(), files.end(), path) == files.end()) files.push_back(path);
  if (std::optional<Transform> to_world = plugin.take_transform("to_world")) {
    const double det = to_world->determinant();
    if (!(std::abs(det) > 0) || !std::isfinite(det)) {
      fail_at(*plugin.property("to_world"),
              "an SDF grid's to_world must be invertible (determinant " + format_number(det) + ")");
    }
    shape.to_world = to_world->matrix();
  }
  if (plugin.property("flip_normals")) {
    fail_at(*plugin.property("flip_normals"),
            "an sdfgrid has no flip_normals (Mitsuba refuses it as an unreferenced property); "
            "negate the grid's values instead");
  }
  if (!plugin.take_objects("emitter").empty()) {
    fail_at(plugin.element(), "an sdfgrid cannot emit light (as in Mitsuba, which cannot sample it)");
  }
  shape.material = read_material(plugin, context, false);
  refuse_media(plugin);
  plugin.finish();
  return shape;
}

Shape read_instance(MitsubaPlugin& plugin, MitsubaShapeContext& context) {
  std::vector<MitsubaObject> groups = plugin.take_objects("shape");
  if (groups.size() != 1) {
    fail_at(plugin.element(), "an instance names one shapegroup (<ref id=\"...\"/>)");
  }
  const std::string* type = groups.front().element->attribute("type");
  if (!type || *type != "shapegroup") {
    fail_at(*groups.front().written, "an instance places a shapegroup");
  }
  Shape shape;
  shape.kind = Shape::Kind::instance;
  shape.origin = plugin.element().where();
  shape.group = read_mitsuba_shape_group(*groups.front().element, context);
  shape.to_world = plugin.take_transform("to_world").value_or(Transform()).matrix();
  plugin.finish();
  return shape;
}

}  // namespace

Shape read_mitsuba_shape(const MitsubaElement& element, MitsubaShapeContext& context) {
  MitsubaPlugin plugin(element, context.ids);
  const std::string& type = plugin.type();
  if (type == "instance") return read_instance(plugin, context);
  if (type == "linearcurve" || type == "bsplinecurve") return read_curves(plugin, context);
  if (type == "sdfgrid") return read_sdfgrid(plugin, context);
  if (type == "shapegroup") {
    fail_at(element, "a shapegroup belongs at the top of the scene (instances place it)");
  }
  bool is_file = type == "obj" || type == "ply" || type == "serialized";
  if (!is_file && type != "rectangle" && type != "cube" && type != "disk" && type != "sphere" &&
      type != "cylinder") {
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
      // The OBJ reader flips v as Mitsuba does by default (flip_tex_coords true).
      bool flip_v = type == "obj" && !plugin.take_boolean("flip_tex_coords").value_or(true);
      mesh = type == "serialized" ? load_serialized(plugin, context, face_normals)
                                  : load_file(plugin, context, face_normals, dropped);
      if (flip_v) {
        for (glm::dvec2& uv : mesh.uvs) uv.y = 1 - uv.y;
      }
      shape.uvs = mesh.uvs;
    } else {
      MitsubaBuiltinMesh builtin = type == "rectangle"  ? mitsuba_rectangle()
                                   : type == "cube"     ? mitsuba_cube()
                                   : type == "cylinder" ? mitsuba_cylinder()
                                                        : mitsuba_disk();
      if (type == "cylinder") to_world = cylinder_placement(plugin).then(to_world);
      mesh = std::move(builtin.mesh);
      shape.uvs = std::move(builtin.uvs);
    }
    place_mesh(mesh, to_world, flip, is_file, face_normals, dropped, element);
    shape.positions = std::move(mesh.positions);
    shape.normals = std::move(mesh.normals);
    shape.indices = std::move(mesh.indices);
    shape.attributes = std::move(mesh.attributes);  // PLY files' (mesh_attribute textures)
    shape.dropped_triangles = dropped;
  }
  bool emitter = read_emitter(plugin, context, shape);
  shape.material = read_material(plugin, context, emitter);
  read_media(plugin, context, shape);
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

bool mitsuba_shape_is_empty(const Shape& shape) {
  return shape.kind == Shape::Kind::triangles && shape.indices.empty();
}

void note_empty_mitsuba_shape(const Shape& shape) {
  std::fprintf(stderr,
               "note: %s: all %llu faces of its mesh are degenerate (zero area): left out, as "
               "no ray hits it in Mitsuba either\n",
               shape.origin.c_str(), static_cast<unsigned long long>(shape.dropped_triangles));
}

uint32_t read_mitsuba_shape_group(const MitsubaElement& element, MitsubaShapeContext& context) {
  auto it = context.group_index.find(&element);
  if (it != context.group_index.end()) return it->second;
  MitsubaPlugin plugin(element, context.ids);
  ShapeGroup group;
  const std::string* id = element.attribute("id");
  group.name = id ? *id : "shapegroup (" + element.file + " line " + std::to_string(element.line) + ")";
  group.origin = element.where();
  for (const MitsubaObject& member : plugin.take_objects("shape")) {
    const std::string* type = member.element->attribute("type");
    if (type && (*type == "instance" || *type == "shapegroup")) {
      fail_at(*member.written, "a shapegroup holds shapes, not instances or groups");
    }
    const size_t lights_before = context.lights.size();
    Shape shape = read_mitsuba_shape(*member.element, context);
    if (shape.is_emitter() || context.lights.size() != lights_before) {
      fail_at(*member.written, "a shapegroup's shapes cannot emit light (as in Mitsuba)");
    }
    if (shape.bounds_medium()) {
      fail_at(*member.written, "a shapegroup's shapes cannot bound a medium in Tessera");
    }
    if (mitsuba_shape_is_empty(shape)) {
      note_empty_mitsuba_shape(shape);
      continue;
    }
    group.shapes.push_back(std::move(shape));
  }
  if (group.shapes.empty()) fail_at(element, "a shapegroup needs at least one shape");
  plugin.finish();
  context.groups.push_back(std::move(group));
  uint32_t index = uint32_t(context.groups.size() - 1);
  context.group_index[&element] = index;
  return index;
}

}  // namespace tessera
