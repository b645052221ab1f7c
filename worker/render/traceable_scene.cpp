#include "traceable_scene.h"

#include <cmath>
#include <cstring>
#include <limits>

#include <glm/geometric.hpp>

#include "scene/scene_error.h"
#include "sphere_intersector.h"

namespace tessera {
namespace {

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

}  // namespace

TraceableScene::TraceableScene(const Scene& scene, int width, int height, const std::string& isa)
    : camera_(scene.camera, width, height) {
  const std::string config = isa.empty() ? std::string() : "isa=" + isa;
  device_ = rtcNewDevice(config.empty() ? nullptr : config.c_str());
  if (!device_) {
    throw SceneError("Embree device creation failed" +
                     (isa.empty() ? std::string() : " (isa=" + isa + ")"));
  }
  rtcSetDeviceErrorFunction(device_, on_device_error, &device_error_);
  isa_ = isa.empty() ? isa_name(device_) : isa;

  for (const Material& m : scene.materials) {
    materials_.push_back({m.type, glm::vec3(m.reflectance.value), float(m.ior), m.two_sided});
  }

  scene_ = rtcNewScene(device_);
  rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
  for (const Shape& shape : scene.shapes) {
    if (shape.kind == Shape::Kind::sphere) {
      add_sphere(shape);
    } else {
      add_triangles(shape);
    }
  }
  rtcCommitScene(scene_);
  if (!device_error_.empty()) throw SceneError(device_error_);

  for (auto& g : geometries_) {
    if (g->emission.x > 0 || g->emission.y > 0 || g->emission.z > 0) {
      g->emitter = int32_t(emitters_.size());
      emitters_.emplace_back(*g);
    }
  }
  light_selector_ = std::make_unique<LightSelector>(emitters_);
}

TraceableScene::~TraceableScene() {
  if (scene_) rtcReleaseScene(scene_);
  if (device_) rtcReleaseDevice(device_);
}

void TraceableScene::add_triangles(const Shape& shape) {
  auto g = std::make_unique<Geometry>();
  g->kind = Geometry::Kind::triangles;
  g->positions.reserve(shape.positions.size());
  for (const glm::dvec3& p : shape.positions) g->positions.emplace_back(p);
  for (const glm::dvec3& n : shape.normals) g->normals.push_back(glm::normalize(glm::vec3(n)));
  g->indices = shape.indices;
  for (const glm::u32vec3& tri : g->indices) {
    const glm::vec3 p0 = g->positions[tri.x], p1 = g->positions[tri.y], p2 = g->positions[tri.z];
    const glm::dvec3 n = glm::cross(glm::dvec3(p1) - glm::dvec3(p0), glm::dvec3(p2) - glm::dvec3(p0));
    g->face_normals.emplace_back(glm::normalize(n));
    g->point_errors.push_back(triangle_point_error(p0, p1, p2));
  }
  g->material = shape.material;
  g->emission = glm::vec3(shape.emission);
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
  rtcCommitGeometry(geom);
  const unsigned id = rtcAttachGeometry(scene_, geom);
  rtcReleaseGeometry(geom);
  if (id != geometries_.size()) throw SceneError("Embree geometry ids out of sequence");
  geometries_.push_back(std::move(g));
}

void TraceableScene::add_sphere(const Shape& shape) {
  auto g = std::make_unique<Geometry>();
  g->kind = Geometry::Kind::sphere;
  g->center = shape.center;
  g->radius = shape.radius;
  g->inward = shape.flip_normals;
  g->material = shape.material;
  g->emission = glm::vec3(shape.emission);
  g->two_sided_emission = shape.two_sided_emission;

  RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
  attach_sphere_callbacks(geom, g.get());
  rtcCommitGeometry(geom);
  const unsigned id = rtcAttachGeometry(scene_, geom);
  rtcReleaseGeometry(geom);
  if (id != geometries_.size()) throw SceneError("Embree geometry ids out of sequence");
  geometries_.push_back(std::move(g));
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

  const Geometry& g = *geometries_[rh.hit.geomID];
  hit->geometry = &g;
  hit->primitive = rh.hit.primID;
  if (g.kind == Geometry::Kind::sphere) {
    // Re-project the hit onto the sphere in double: the point is then accurate to float
    // rounding, whatever the error of t.
    const glm::dvec3 p = glm::dvec3(ray.o) + double(rh.ray.tfar) * glm::dvec3(ray.d);
    glm::dvec3 n = glm::normalize(p - g.center);
    const glm::dvec3 on_sphere = g.center + g.radius * n;
    if (g.inward) n = -n;
    hit->sp.p = glm::vec3(on_sphere);
    hit->sp.p_error = gamma_bound(5) * glm::abs(hit->sp.p);
    hit->sp.ng = glm::vec3(n);
    hit->ns = hit->sp.ng;
    return true;
  }
  const glm::u32vec3 tri = g.indices[rh.hit.primID];
  const glm::vec3 p0 = g.positions[tri.x], p1 = g.positions[tri.y], p2 = g.positions[tri.z];
  const float b1 = rh.hit.u, b2 = rh.hit.v, b0 = 1.0f - b1 - b2;
  hit->sp.p = b0 * p0 + b1 * p1 + b2 * p2;
  hit->sp.p_error = glm::vec3(g.point_errors[rh.hit.primID]);
  hit->sp.ng = g.face_normals[rh.hit.primID];
  if (g.normals.empty()) {
    hit->ns = hit->sp.ng;
  } else {
    glm::vec3 ns = b0 * g.normals[tri.x] + b1 * g.normals[tri.y] + b2 * g.normals[tri.z];
    const float len = glm::length(ns);
    ns = len > 0 ? ns / len : hit->sp.ng;
    hit->ns = glm::dot(ns, hit->sp.ng) < 0 ? -ns : ns;
  }
  return true;
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
