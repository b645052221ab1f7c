#include "render/scene/traceable_scene.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "render/geometry/curve.h"
#include "render/geometry/sdf_grid.h"
#include "render/geometry/sphere_intersector.h"
#include "render/sampling/warp.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

/// Whether a material's roughness differs along dpdu and dpdv anywhere (rough kinds with
/// alpha_u != alpha_v or textured alphas, principled kinds with a non-zero or textured
/// `anisotropic`, hair, a blend holding either): its shading frame then follows dpdu (hair's
/// +y runs along the fibre: on a curve, dpdu goes around it).
bool is_anisotropic(const Material& m) {
  if (m.type == MaterialType::hair) return true;
  if (m.alpha_u.value != m.alpha_v.value || !m.alpha_u.is_constant() || !m.alpha_v.is_constant()) {
    return true;
  }
  if ((m.type == MaterialType::principled || m.type == MaterialType::principled_thin) &&
      (m.principled.anisotropic.value != 0 || !m.principled.anisotropic.is_constant())) {
    return true;
  }
  for (const Material& nested : m.blend) {
    if (is_anisotropic(nested)) return true;
  }
  return false;
}

void on_device_error(void* user, RTCError code, const char* message) {
  auto* out = static_cast<std::string*>(user);
  if (out->empty()) {
    *out = "Embree error " + std::to_string(int(code)) + ": " + (message ? message : "");
  }
}

std::string isa_name(RTCDevice device) {
  // Embree reports the widest native ray-packet width the device was built for.
  const ssize_t avx512 = rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED);
  const ssize_t avx = rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED);
  if (avx512) return "avx512";
  if (avx) return "avx2";
  return "sse4.2";
}

glm::vec3 transform_point(const glm::mat4& m, glm::vec3 p) { return glm::vec3(m * glm::vec4(p, 1.0f)); }
glm::vec3 transform_vector(const glm::mat4& m, glm::vec3 v) { return glm::mat3(m) * v; }

}  // namespace

TraceableScene::TraceableScene(const Scene& scene, int width, int height, const std::string& isa,
                               const FileReader& reader)
    : camera_(scene.camera, width, height), hide_emitters_(scene.render.hide_emitters),
      rr_depth_(scene.render.rr_depth) {
  // Embree's objects are plain handles: when building fails, release what was made, since the
  // destructor does not run for an object that was never constructed.
  try {
    build(scene, isa, reader);
  } catch (...) {
    release();
    throw;
  }
}

void TraceableScene::build(const Scene& scene, const std::string& isa, const FileReader& reader) {
  const FileReader files = reader        ? reader
                           : scene.files ? scene.files
                                         : FileReader([](const std::string& path) -> std::string {
                                             throw SceneError(path + ": the scene was not loaded from files, so " +
                                                              "the renderer cannot read it");
                                           });
  textures_ = std::make_unique<TextureSet>(scene.textures, files);
  const std::string config = isa.empty() ? std::string() : "isa=" + isa;
  device_ = rtcNewDevice(config.empty() ? nullptr : config.c_str());
  if (!device_) {
    throw SceneError("Embree device creation failed" +
                     (isa.empty() ? std::string() : " (isa=" + isa + ")"));
  }
  rtcSetDeviceErrorFunction(device_, on_device_error, &device_error_);
  isa_ = isa.empty() ? isa_name(device_) : isa;

  for (const Material& m : scene.materials) {
    materials_.push_back(make_render_material(m, rough_plastic_tables_));
    // Anisotropic roughness is measured along dpdu: the shading frame then needs it.
    if (is_anisotropic(m)) need_uv_ = true;
  }
  // uvs and their tangents cost an atan2 and an acos per sphere hit: only where used.
  if (!scene.textures.empty()) need_uv_ = true;

  build_groups(scene);
  build_shapes(scene);
  build_media(scene);
  build_lights(scene, files);
}

/// Shape groups first: each is an Embree scene of its own that instances place.
void TraceableScene::build_groups(const Scene& scene) {
  for (const ShapeGroup& group : scene.groups) {
    RTCScene gs = rtcNewScene(device_);
    rtcSetSceneFlags(gs, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(gs, RTC_BUILD_QUALITY_HIGH);
    group_scenes_.push_back(gs);
    group_geometries_.emplace_back();
    for (const Shape& shape : group.shapes) {
      if (shape.kind == Shape::Kind::instance) {
        throw SceneError(shape.origin + ": a shape group cannot hold an instance");
      }
      if (shape.is_emitter()) {
        throw SceneError(shape.origin + ": a shape group cannot hold an emitter");
      }
      auto g = shape.kind == Shape::Kind::sphere    ? add_sphere(shape, gs)
               : shape.kind == Shape::Kind::curves  ? add_curves(shape, gs)
               : shape.kind == Shape::Kind::sdfgrid ? add_sdfgrid(shape, gs)
                                                    : add_triangles(shape, gs, scene.textures);
      group_geometries_.back().push_back(std::move(g));
    }
    rtcCommitScene(gs);
    if (!device_error_.empty()) throw SceneError(group.origin + ": " + device_error_);
  }
}

/// The top-level shapes, instances of the groups among them.
void TraceableScene::build_shapes(const Scene& scene) {
  scene_ = rtcNewScene(device_);
  rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
  for (const Shape& shape : scene.shapes) {
    if (shape.kind == Shape::Kind::sphere) {
      geometries_.push_back(add_sphere(shape, scene_));
    } else if (shape.kind == Shape::Kind::instance) {
      add_instance(shape, group_scenes_);
    } else if (shape.kind == Shape::Kind::curves) {
      geometries_.push_back(add_curves(shape, scene_));
    } else if (shape.kind == Shape::Kind::sdfgrid) {
      geometries_.push_back(add_sdfgrid(shape, scene_));
    } else {
      geometries_.push_back(add_triangles(shape, scene_, scene.textures));
    }
  }
  rtcCommitScene(scene_);
  if (!device_error_.empty()) throw SceneError(device_error_);
}

/// Media: only when something uses one, so that a scene without pays nothing.
void TraceableScene::build_media(const Scene& scene) {
  for (const Medium& m : scene.media) media_.push_back(make_render_medium(m, scene.textures));
  auto check_medium = [&](int32_t index, const std::string& origin) {
    if (index >= int32_t(media_.size())) throw SceneError(origin + ": medium index out of range");
    if (index >= 0) has_media_ = true;
  };
  check_medium(scene.camera.medium, "the camera");
  camera_medium_ = scene.camera.medium;
  for (const Shape& shape : scene.shapes) {
    check_medium(shape.interior, shape.origin);
    check_medium(shape.exterior, shape.origin);
    if (shape.bounds_medium() && shape.kind != Shape::Kind::triangles && shape.kind != Shape::Kind::sphere) {
      throw SceneError(shape.origin + ": only triangles and spheres can bound a medium");
    }
  }
  if (has_media_) {
    if (geometries_.size() != scene.shapes.size()) {
      throw SceneError("internal: one top-level geometry per shape expected");
    }
    for (const Shape& shape : scene.shapes) medium_sides_.push_back({shape.interior, shape.exterior});
  }
}

/// The lights (area emitters among the shapes, then the scene's lights) and the specular
/// targets, both sized by the scene's bounds.
void TraceableScene::build_lights(const Scene& scene, const FileReader& files) {
  std::vector<const Geometry*> area_emitters;
  for (auto& g : geometries_) {
    if (g->emission.x > 0 || g->emission.y > 0 || g->emission.z > 0) {
      g->emitter = int32_t(area_emitters.size());
      area_emitters.push_back(g.get());
    }
  }
  // Directional and environment lights are weighed by their power through the scene's
  // bounding disc: the radius of the sphere around its bounding box.
  RTCBounds bounds;
  rtcGetSceneBounds(scene_, &bounds);
  float scene_radius = 0;
  if (bounds.lower_x <= bounds.upper_x) {
    const glm::vec3 lo(bounds.lower_x, bounds.lower_y, bounds.lower_z);
    const glm::vec3 hi(bounds.upper_x, bounds.upper_y, bounds.upper_z);
    scene_radius = 0.5f * glm::length(hi - lo);
    const glm::vec3 reach = glm::max(glm::abs(lo), glm::abs(hi));
    reach_ = std::max(reach.x, std::max(reach.y, reach.z));
  }
  const TextureSet* textures = textures_.get();
  lights_ = std::make_unique<LightSet>(
      area_emitters, scene.lights, files,
      [textures](int32_t texture, glm::vec2 uv) { return textures->lookup(texture, uv); },
      scene_radius);
  std::vector<SpecularTargets::ShapeRef> shapes;
  for (const auto& g : geometries_) {
    if (g->kind != Geometry::Kind::instance) {
      shapes.push_back({g.get(), nullptr});
    } else {
      for (const auto& member : group_geometries_[g->group]) shapes.push_back({member.get(), &g->to_world});
    }
  }
  specular_targets_ = SpecularTargets(shapes, materials_, scene_radius);
}

void TraceableScene::release() {
  if (scene_) rtcReleaseScene(scene_);
  scene_ = nullptr;
  for (RTCScene gs : group_scenes_) rtcReleaseScene(gs);
  group_scenes_.clear();
  if (device_) rtcReleaseDevice(device_);
  device_ = nullptr;
}

TraceableScene::~TraceableScene() { release(); }

void TraceableScene::attach(RTCGeometry geom, RTCScene target, size_t expected_id,
                            const std::string& origin) {
  rtcCommitGeometry(geom);
  const unsigned id = rtcAttachGeometry(target, geom);
  rtcReleaseGeometry(geom);
  if (id != expected_id) throw SceneError(origin + ": Embree geometry ids out of sequence");
}

std::unique_ptr<Geometry> TraceableScene::add_triangles(const Shape& shape, RTCScene target,
                                                        const std::vector<Texture>& textures) {
  auto g = std::make_unique<Geometry>();
  g->kind = Geometry::Kind::triangles;
  g->positions.reserve(shape.positions.size());
  for (const glm::dvec3& p : shape.positions) g->positions.emplace_back(p);
  for (const glm::dvec3& n : shape.normals) g->normals.push_back(glm::normalize(glm::vec3(n)));
  if (!shape.uvs.empty()) {
    if (shape.uvs.size() != shape.positions.size()) {
      throw SceneError(shape.origin + ": " + std::to_string(shape.uvs.size()) + " uvs for " +
                       std::to_string(shape.positions.size()) + " vertices");
    }
    g->uvs.reserve(shape.uvs.size());
    for (const glm::dvec2& uv : shape.uvs) g->uvs.emplace_back(uv);
  }
  g->indices = shape.indices;
  if (!shape.attributes.empty()) g->attributes = MeshAttributeTable(shape, textures);
  for (const glm::u32vec3& tri : g->indices) {
    const glm::vec3 p0 = g->positions[tri.x], p1 = g->positions[tri.y], p2 = g->positions[tri.z];
    const glm::dvec3 n = glm::cross(glm::dvec3(p1) - glm::dvec3(p0), glm::dvec3(p2) - glm::dvec3(p0));
    g->face_normals.emplace_back(glm::normalize(n));
    g->point_errors.push_back(triangle_point_error(p0, p1, p2));
  }
  g->material = shape.material;
  g->emission = glm::vec3(shape.emission);
  g->emission_texture = shape.emission_texture;
  g->two_sided_emission = shape.two_sided_emission;

  RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), g->positions.size()));
  auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), g->indices.size()));
  if (!vertices || !indices) {
    rtcReleaseGeometry(geom);
    throw SceneError(shape.origin + ": Embree could not allocate the mesh (" + device_error_ + ")");
  }
  std::memcpy(vertices, g->positions.data(), g->positions.size() * 3 * sizeof(float));
  std::memcpy(indices, g->indices.data(), g->indices.size() * 3 * sizeof(uint32_t));
  const size_t expected = target == scene_ ? geometries_.size() : group_geometries_.back().size();
  attach(geom, target, expected, shape.origin);
  return g;
}

std::unique_ptr<Geometry> TraceableScene::add_sphere(const Shape& shape, RTCScene target) {
  auto g = std::make_unique<Geometry>();
  g->kind = Geometry::Kind::sphere;
  g->center = shape.center;
  g->radius = shape.radius;
  g->inward = shape.flip_normals;
  g->frame = glm::mat3(shape.frame);
  g->material = shape.material;
  g->emission = glm::vec3(shape.emission);
  g->emission_texture = shape.emission_texture;
  g->two_sided_emission = shape.two_sided_emission;

  RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
  attach_sphere_callbacks(geom, g.get());
  const size_t expected = target == scene_ ? geometries_.size() : group_geometries_.back().size();
  attach(geom, target, expected, shape.origin);
  return g;
}

std::unique_ptr<Geometry> TraceableScene::add_curves(const Shape& shape, RTCScene target) {
  auto g = std::make_unique<Geometry>();
  RTCGeometry geom = new_curve_geometry(device_, shape, *g);
  if (!geom) {
    throw SceneError(shape.origin + ": Embree could not allocate the curves (" + device_error_ + ")");
  }
  const size_t expected = target == scene_ ? geometries_.size() : group_geometries_.back().size();
  attach(geom, target, expected, shape.origin);
  return g;
}

std::unique_ptr<Geometry> TraceableScene::add_sdfgrid(const Shape& shape, RTCScene target) {
  if (shape.is_emitter()) throw SceneError(shape.origin + ": an SDF grid cannot emit light");
  auto g = std::make_unique<Geometry>();
  g->kind = Geometry::Kind::sdfgrid;
  g->sdf = std::make_shared<const SdfGrid>(shape);
  g->material = shape.material;
  RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
  attach_sdf_grid_callbacks(geom, g->sdf.get());
  const size_t expected = target == scene_ ? geometries_.size() : group_geometries_.back().size();
  attach(geom, target, expected, shape.origin);
  return g;
}

void TraceableScene::add_instance(const Shape& shape, const std::vector<RTCScene>& group_scenes) {
  if (shape.group >= group_scenes.size()) {
    throw SceneError(shape.origin + ": instance of shape group " + std::to_string(shape.group) +
                     ", but the scene has " + std::to_string(group_scenes.size()));
  }
  auto g = std::make_unique<Geometry>();
  g->kind = Geometry::Kind::instance;
  g->group = shape.group;
  g->to_world = glm::mat4(shape.to_world);
  const glm::dmat4 inverse = glm::inverse(shape.to_world);
  g->to_object = glm::mat4(inverse);
  g->normal_to_world = glm::mat3(glm::transpose(glm::dmat3(inverse)));
  // A point mapped by the float matrix: 3 products and 3 sums per coordinate.
  g->transform_error = gamma_bound(4);

  RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
  rtcSetGeometryInstancedScene(geom, group_scenes[shape.group]);
  rtcSetGeometryTimeStepCount(geom, 1);
  float xfm[12];  // column-major 3x4
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 3; ++r) xfm[c * 3 + r] = g->to_world[c][r];
  }
  rtcSetGeometryTransform(geom, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm);
  attach(geom, scene_, geometries_.size(), shape.origin);
  geometries_.push_back(std::move(g));
}

void TraceableScene::fill_sphere_hit(const Geometry& g, const glm::vec3& o, const glm::vec3& d,
                                     float t, Hit* hit) const {
  // Re-project the hit onto the sphere in double: the point is then accurate to float
  // rounding, whatever the error of t.
  const glm::dvec3 p = glm::dvec3(o) + double(t) * glm::dvec3(d);
  glm::dvec3 n = glm::normalize(p - g.center);
  const glm::dvec3 on_sphere = g.center + g.radius * n;
  hit->sp.p = glm::vec3(on_sphere);
  hit->sp.p_error = gamma_bound(5) * glm::abs(hit->sp.p);
  hit->sp.ng = glm::vec3(g.inward ? -n : n);
  hit->ns = hit->sp.ng;
  if (!need_uv_) return;
  // Mitsuba's parametrisation, in the sphere's own (rotated) frame.
  const glm::vec3 local = glm::transpose(g.frame) * glm::vec3(n);
  const float theta = std::acos(std::clamp(local.z, -1.0f, 1.0f));
  float phi = std::atan2(local.y, local.x);
  if (phi < 0) phi += 2 * kPi;
  hit->uv = {phi / (2 * kPi), theta / kPi};
  const float rd = std::sqrt(local.x * local.x + local.y * local.y);
  const float r = float(g.radius);
  hit->dpdu = g.frame * glm::vec3(-local.y, local.x, 0.0f) * (2 * kPi * r);
  hit->dpdv = rd > 0 ? g.frame * glm::vec3(local.z * local.x / rd, local.z * local.y / rd, -rd) * (kPi * r)
                     : g.frame * glm::vec3(1, 0, 0) * (kPi * r);
}

void TraceableScene::fill_sdf_hit(const Geometry& g, const glm::vec3& o, const glm::vec3& d, float t,
                                  uint32_t primitive, float voxel, Hit* hit) const {
  const SdfGridHit h = g.sdf->hit(primitive, uint32_t(voxel), glm::dvec3(o), glm::dvec3(d), double(t));
  hit->sp.p = h.p;
  hit->sp.p_error = h.p_error;
  hit->sp.ng = h.ng;
  hit->ns = glm::dot(h.ns, h.ng) < 0 ? -h.ns : h.ns;
  hit->uv = glm::vec2(0.0f);
  hit->dpdu = glm::vec3(0.0f);
  hit->dpdv = glm::vec3(0.0f);
}

// Inlined into intersect() and make_hit(), as the triangle fill is.
[[gnu::always_inline]] inline void TraceableScene::fill_hit(const Ray& ray, uint32_t geometry_id,
                                                            uint32_t instance_id, uint32_t primitive,
                                                            float t, float b1, float b2, Hit* hit) const {
  if (instance_id != RTC_INVALID_GEOMETRY_ID) {
    fill_instance_hit(ray, instance_id, geometry_id, primitive, t, b1, b2, hit);
    return;
  }
  const Geometry& g = *geometries_[geometry_id];
  hit->geometry = &g;
  hit->primitive = primitive;
  hit->geometry_id = geometry_id;
  if (g.kind == Geometry::Kind::sphere) {
    fill_sphere_hit(g, ray.o, ray.d, t, hit);
  } else if (g.kind == Geometry::Kind::curves) [[unlikely]] {
    fill_curve_hit(g, ray.o, ray.d, t, primitive, b1, need_uv_, hit);
  } else if (g.kind == Geometry::Kind::sdfgrid) [[unlikely]] {
    fill_sdf_hit(g, ray.o, ray.d, t, primitive, b1, hit);
  } else {
    fill_triangle_hit(g, primitive, b1, b2, hit);
  }
}

bool TraceableScene::intersect(const Ray& ray, Hit* hit) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  rh.ray.org_x = ray.o.x;
  rh.ray.org_y = ray.o.y;
  rh.ray.org_z = ray.o.z;
  rh.ray.dir_x = ray.d.x;
  rh.ray.dir_y = ray.d.y;
  rh.ray.dir_z = ray.d.z;
  rh.ray.tnear = 0.0f;
  rh.ray.tfar = ray.t_max;
  rh.ray.time = 0.0f;
  rh.ray.mask = 0xffffffffu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  fill_hit(ray, rh.hit.geomID, rh.hit.instID[0], rh.hit.primID, rh.ray.tfar, rh.hit.u, rh.hit.v, hit);
  return true;
}

void TraceableScene::make_hit_other(const Ray& ray, uint32_t geometry_id, uint32_t instance_id, uint32_t primitive,
                                    float t, float b1, float b2, Hit* hit) const {
  const Geometry& g = instance_id == RTC_INVALID_GEOMETRY_ID
                          ? *geometries_[geometry_id]
                          : *group_geometries_[geometries_[instance_id]->group][geometry_id];
  // Embree's packet and single-ray curve intersectors round differently: a curve hit found by
  // a packet is traced again alone, so that both integrators give the same bits.
  // So are user geometries inside instances (the ray reaches them through Embree's transform):
  // SDF grids are traced again too.
  if ((g.kind == Geometry::Kind::curves || g.kind == Geometry::Kind::sdfgrid) && intersect(ray, hit)) [[unlikely]] {
    return;
  }
  fill_hit(ray, geometry_id, instance_id, primitive, t, b1, b2, hit);
}

// Out of line: scenes without instances keep intersect() short (fewer registers to save).
[[gnu::noinline]] void TraceableScene::fill_instance_hit(const Ray& ray, uint32_t instance_id,
                                                         uint32_t geometry_id, uint32_t primitive, float t,
                                                         float b1, float b2, Hit* hit) const {
  // A shape of a group, placed by an instance: find the hit in the group's space, then map the
  // point, its error bound, the normals and the tangents to the world.
  const Geometry& inst = *geometries_[instance_id];
  const Geometry& g = *group_geometries_[inst.group][geometry_id];
  hit->geometry = &g;
  hit->primitive = primitive;
  hit->geometry_id = instance_id;
  if (g.kind == Geometry::Kind::sphere) {
    fill_sphere_hit(g, transform_point(inst.to_object, ray.o), transform_vector(inst.to_object, ray.d), t, hit);
  } else if (g.kind == Geometry::Kind::curves) {
    fill_curve_hit(g, transform_point(inst.to_object, ray.o), transform_vector(inst.to_object, ray.d), t,
                   primitive, b1, need_uv_, hit);
  } else if (g.kind == Geometry::Kind::sdfgrid) {
    fill_sdf_hit(g, transform_point(inst.to_object, ray.o), transform_vector(inst.to_object, ray.d), t,
                 primitive, b1, hit);
  } else {
    fill_triangle_hit(g, primitive, b1, b2, hit);
  }
  const glm::vec3 p_object = hit->sp.p;
  hit->sp.p = transform_point(inst.to_world, p_object);
  // |M p| and |M| |err| bound the mapped point's error: the object-space error carried
  // through the matrix, plus the rounding of the product itself.
  const glm::mat3 abs_m = glm::mat3(glm::abs(glm::vec3(inst.to_world[0])), glm::abs(glm::vec3(inst.to_world[1])),
                                    glm::abs(glm::vec3(inst.to_world[2])));
  hit->sp.p_error = abs_m * hit->sp.p_error * (1 + inst.transform_error) +
                    inst.transform_error * (abs_m * glm::abs(p_object) + glm::abs(glm::vec3(inst.to_world[3])));
  hit->sp.ng = glm::normalize(inst.normal_to_world * hit->sp.ng);
  glm::vec3 ns = glm::normalize(inst.normal_to_world * hit->ns);
  hit->ns = glm::dot(ns, hit->sp.ng) < 0 ? -ns : ns;
  hit->dpdu = transform_vector(inst.to_world, hit->dpdu);
  hit->dpdv = transform_vector(inst.to_world, hit->dpdv);
}

bool TraceableScene::occluded(glm::vec3 o, glm::vec3 d, float t_max) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay r;
  r.org_x = o.x;
  r.org_y = o.y;
  r.org_z = o.z;
  r.dir_x = d.x;
  r.dir_y = d.y;
  r.dir_z = d.z;
  r.tnear = 0.0f;
  r.tfar = t_max;
  r.time = 0.0f;
  r.mask = 0xffffffffu;
  r.id = 0;
  r.flags = 0;
  rtcOccluded1(scene_, &context, &r);
  return r.tfar < 0.0f;
}

}  // namespace tessera
