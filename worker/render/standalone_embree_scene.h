// An Embree scene built from a Scene's shapes the way TraceableScene builds its own (same
// scene flags and build quality, geometry ids in shape order, spheres through the same
// double-precision user geometry), for the packet tracer's tests and tessera-bench-rays.
// TraceableScene keeps its RTCScene private; once it exposes it (one accessor,
// `RTCScene embree_scene() const { return scene_; }`), callers trace that one instead.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <embree3/rtcore.h>

#include "geometry.h"
#include "scene/scene.h"
#include "scene/scene_error.h"
#include "sphere_intersector.h"

namespace tessera {

class StandaloneEmbreeScene {
 public:
  /// `isa` pins Embree's instruction set ("avx2", ...); empty lets Embree choose.
  /// Throws SceneError when Embree refuses the device or the geometry.
  StandaloneEmbreeScene(const Scene& scene, const std::string& isa) {
    const std::string config = isa.empty() ? std::string() : "isa=" + isa;
    device_ = rtcNewDevice(config.empty() ? nullptr : config.c_str());
    if (!device_) throw SceneError("Embree device creation failed (isa=" + isa + ")");
    scene_ = rtcNewScene(device_);
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    for (const Shape& shape : scene.shapes) {
      if (shape.kind != Shape::Kind::sphere && shape.kind != Shape::Kind::triangles) {
        throw SceneError(shape.origin + ": only triangles and spheres are copied into a standalone Embree scene");
      }
      auto g = std::make_unique<Geometry>();
      RTCGeometry geom;
      if (shape.kind == Shape::Kind::sphere) {
        g->kind = Geometry::Kind::sphere;
        g->center = shape.center;
        g->radius = shape.radius;
        geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
        attach_sphere_callbacks(geom, g.get());
      } else {
        for (const glm::dvec3& p : shape.positions) g->positions.emplace_back(p);
        g->indices = shape.indices;
        geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
        rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, g->positions.data(), 0,
                                   sizeof(glm::vec3), g->positions.size());
        rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, g->indices.data(), 0,
                                   sizeof(glm::u32vec3), g->indices.size());
      }
      rtcCommitGeometry(geom);
      const unsigned id = rtcAttachGeometry(scene_, geom);
      rtcReleaseGeometry(geom);
      if (id != geometries_.size()) throw SceneError("Embree geometry ids out of sequence");
      geometries_.push_back(std::move(g));
    }
    rtcCommitScene(scene_);
    if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) throw SceneError(shape_error(scene));
  }
  ~StandaloneEmbreeScene() {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  StandaloneEmbreeScene(const StandaloneEmbreeScene&) = delete;
  StandaloneEmbreeScene& operator=(const StandaloneEmbreeScene&) = delete;

  RTCDevice device() const { return device_; }
  RTCScene scene() const { return scene_; }
  /// Indexed by Embree geometry id (= shape index).
  const Geometry& geometry(uint32_t id) const { return *geometries_[id]; }

 private:
  static std::string shape_error(const Scene& scene) {
    return "Embree refused the geometry of " + std::to_string(scene.shapes.size()) + " shapes";
  }

  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  std::vector<std::unique_ptr<Geometry>> geometries_;
};

}  // namespace tessera
