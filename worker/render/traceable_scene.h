// The immutable render-ready scene: Embree BVH, materials, emitters and the camera, built once
// from the editable Scene description.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <embree3/rtcore.h>

#include "camera.h"
#include "emitter.h"
#include "geometry.h"
#include "material.h"
#include "ray.h"
#include "ray_offset.h"
#include "scene/scene.h"

namespace tessera {

/// What a closest-hit query found.
struct Hit {
  SurfacePoint sp;        ///< point, error bound, unit geometric normal (the shape's front)
  glm::vec3 ns;           ///< unit shading normal, on the same side as sp.ng
  const Geometry* geometry = nullptr;
  uint32_t primitive = 0;
};

class TraceableScene {
 public:
  /// `isa` pins Embree's instruction set ("avx2", ...); empty lets Embree choose.
  /// Throws SceneError when Embree refuses the device or the geometry.
  TraceableScene(const Scene& scene, int width, int height, const std::string& isa);
  ~TraceableScene();
  TraceableScene(const TraceableScene&) = delete;
  TraceableScene& operator=(const TraceableScene&) = delete;

  /// Closest hit along `ray` for t in [0, ray.t_max]; false when the ray escapes.
  bool intersect(const Ray& ray, Hit* hit) const;
  /// True when something blocks o + t d for t in [0, t_max].
  bool occluded(glm::vec3 o, glm::vec3 d, float t_max) const;

  const PerspectiveCamera& camera() const { return camera_; }
  const RenderMaterial& material(uint32_t index) const { return materials_[index]; }
  const std::vector<Emitter>& emitters() const { return emitters_; }
  const LightSelector& light_selector() const { return *light_selector_; }
  /// The instruction set Embree runs with.
  const std::string& isa() const { return isa_; }

 private:
  void add_triangles(const Shape& shape);
  void add_sphere(const Shape& shape);

  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  PerspectiveCamera camera_;
  std::vector<RenderMaterial> materials_;
  std::vector<std::unique_ptr<Geometry>> geometries_;  ///< indexed by Embree geometry id
  std::vector<Emitter> emitters_;
  std::unique_ptr<LightSelector> light_selector_;
  std::string isa_;
  std::string device_error_;
};

}  // namespace tessera
