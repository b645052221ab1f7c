// The immutable render-ready scene: Embree BVH, materials, emitters and the camera, built once
// from the editable Scene description.
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>

#include "render/bsdf/material.h"
#include "render/bsdf/rough_plastic_tables.h"
#include "render/camera/camera.h"
#include "render/geometry/geometry.h"
#include "render/geometry/hit.h"
#include "render/guiding/caustic_guide.h"
#include "render/guiding/specular_targets.h"
#include "render/light/light_set.h"
#include "render/math/ray.h"
#include "render/math/ray_offset.h"
#include "render/media/medium.h"
#include "render/texture/texture_set.h"
#include "scene/file_reader.h"
#include "scene/scene.h"

namespace tessera {

/// The render-ready scene: closest-hit and occlusion queries over Embree, and the materials,
/// lights, media, camera and sampling structures that shade the hits.
class TraceableScene {
 public:
  /// `isa` pins Embree's instruction set ("avx2", ...); empty lets Embree choose. `reader`
  /// serves the files the scene references (bitmap textures, environment maps) by bundle path;
  /// an empty one fails on the first such file. Throws SceneError when Embree refuses the
  /// device or the geometry, or a texture or light cannot be used.
  TraceableScene(const Scene& scene, int width, int height, const std::string& isa,
                 const FileReader& reader = {});
  ~TraceableScene();
  TraceableScene(const TraceableScene&) = delete;
  TraceableScene& operator=(const TraceableScene&) = delete;

  /// Closest hit along `ray` for t in [0, ray.t_max]; false when the ray escapes.
  bool intersect(const Ray& ray, Hit* hit) const;
  /// The Hit that intersect() builds, from Embree's record of a closest hit of `ray` found
  /// elsewhere (a packet query, packet_tracer.h): `geometry_id`, `instance_id` (geomID and
  /// instID[0]; RTC_INVALID_GEOMETRY_ID when not instanced), `primitive`, `t` (tfar) and the
  /// barycentrics `b1`, `b2` (hit u, v). The same fields give the same bits as intersect().
  /// `geometry_id` must not be RTC_INVALID_GEOMETRY_ID.
  ///
  /// Inline for a triangle that is not instanced (the common case, built into each wavefront
  /// kernel's instruction set); every other hit goes out of line (make_hit_other).
  [[gnu::always_inline]] void make_hit(const Ray& ray, uint32_t geometry_id, uint32_t instance_id,
                                       uint32_t primitive, float t, float b1, float b2, Hit* hit) const {
    if (instance_id == RTC_INVALID_GEOMETRY_ID) {
      const Geometry& g = *geometries_[geometry_id];
      if (g.kind == Geometry::Kind::triangles) {
        hit->geometry = &g;
        hit->primitive = primitive;
        hit->geometry_id = geometry_id;
        fill_triangle_hit(g, primitive, b1, b2, hit);
        return;
      }
    }
    make_hit_other(ray, geometry_id, instance_id, primitive, t, b1, b2, hit);
  }
  /// True when something blocks o + t d for t in [0, t_max].
  bool occluded(glm::vec3 o, glm::vec3 d, float t_max) const;

  const ProjectiveCamera& camera() const { return camera_; }
  const RenderMaterial& material(uint32_t index) const { return materials_[index]; }
  /// Every light: area emitters, point, spot, directional and environment lights.
  const LightSet& lights() const { return *lights_; }
  const TextureSet& textures() const { return *textures_; }
  /// The purely specular shapes that diffuse vertices aim some bounces at (specular_targets.h).
  const SpecularTargets& specular_targets() const { return specular_targets_; }
  /// Where light arrives through those shapes, from which directions (caustic_guide.h); empty
  /// until set_caustic_guide() (the renderer builds it: integrators/caustic_photons.h), and for a
  /// scene without targets, lights, or with media.
  const CausticGuide& caustic_guide() const { return caustic_guide_; }
  void set_caustic_guide(CausticGuide guide) { caustic_guide_ = std::move(guide); }
  /// The largest magnitude of a coordinate of the scene's bounds (0 for an empty scene).
  float reach() const { return reach_; }
  /// Whether some shape bounds a medium or the camera sits in one: the renderer then traces
  /// with the volumetric path tracer (integrators/volpath.h).
  bool has_media() const { return has_media_; }
  /// The medium camera rays start in (Camera::medium), -1 = vacuum.
  int32_t camera_medium() const { return camera_medium_; }
  const RenderMedium& medium(int32_t index) const { return media_[size_t(index)]; }
  /// (interior, exterior) media of top-level Embree geometry `embree_id` (-1 = none; always
  /// none for instances, curves and SDF grids).
  glm::ivec2 medium_sides(uint32_t embree_id) const {
    return embree_id < medium_sides_.size() ? medium_sides_[embree_id] : glm::ivec2(-1);
  }
  /// Mitsuba's hide_emitters (RenderSettings).
  bool hide_emitters() const { return hide_emitters_; }
  /// The scattering event Russian roulette starts at, 1 = the camera ray's hit (RenderSettings).
  int rr_depth() const { return rr_depth_; }
  /// Whether hits carry uv, dpdu and dpdv (only when the scene uses them).
  bool has_uv() const { return need_uv_; }
  /// The instruction set Embree runs with.
  const std::string& isa() const { return isa_; }
  /// The committed Embree scene, for queries of many rays at once (packet_tracer.h): Embree
  /// geometry id i is the shape whose Geometry intersect() reports for it. Read-only; lives
  /// as long as this object.
  RTCScene embree_scene() const { return scene_; }
  /// The Geometry of top-level Embree geometry id `embree_id` (a HitBatch's geometry when its
  /// instance is RTC_INVALID_GEOMETRY_ID); must be < the number of top-level shapes.
  const Geometry& geometry(uint32_t embree_id) const { return *geometries_[embree_id]; }
  /// The Embree device, for its properties (PacketTracer::native_width).
  RTCDevice embree_device() const { return device_; }

 private:
  void build(const Scene& scene, const std::string& isa, const FileReader& reader);
  void build_groups(const Scene& scene);
  void build_shapes(const Scene& scene);
  void build_media(const Scene& scene);
  void build_lights(const Scene& scene, const FileReader& files);
  /// Releases the Embree scenes and device (the Geometry tables are members).
  void release();
  /// Builds the Geometry and Embree geometry of `shape` and attaches it to `target`.
  /// `transform` places a group's sphere in the world (spheres are not instanced).
  /// `textures`: the scene's, whose mesh_attribute textures say which attributes to keep.
  std::unique_ptr<Geometry> add_triangles(const Shape& shape, RTCScene target,
                                          const std::vector<Texture>& textures);
  std::unique_ptr<Geometry> add_sphere(const Shape& shape, RTCScene target);
  std::unique_ptr<Geometry> add_curves(const Shape& shape, RTCScene target);
  std::unique_ptr<Geometry> add_sdfgrid(const Shape& shape, RTCScene target);
  void add_instance(const Shape& shape, const std::vector<RTCScene>& group_scenes);
  void attach(RTCGeometry geom, RTCScene target, size_t expected_id, const std::string& origin);
  /// make_hit() for every hit but a triangle that is not instanced.
  void make_hit_other(const Ray& ray, uint32_t geometry_id, uint32_t instance_id, uint32_t primitive,
                      float t, float b1, float b2, Hit* hit) const;
  /// Inline (defined below the class): make_hit(), intersect() and fill_instance_hit().
  void fill_triangle_hit(const Geometry& g, uint32_t primitive, float b1, float b2, Hit* hit) const;
  void fill_sphere_hit(const Geometry& g, const glm::vec3& o, const glm::vec3& d, float t, Hit* hit) const;
  /// `voxel`: the hit's Embree u (geometry/sdf_grid.h).
  void fill_sdf_hit(const Geometry& g, const glm::vec3& o, const glm::vec3& d, float t, uint32_t primitive,
                    float voxel, Hit* hit) const;
  /// make_hit(), inlined into intersect().
  void fill_hit(const Ray& ray, uint32_t geometry_id, uint32_t instance_id, uint32_t primitive, float t,
                float b1, float b2, Hit* hit) const;
  /// The hit of a shape reached through an instance, mapped to the world.
  void fill_instance_hit(const Ray& ray, uint32_t instance_id, uint32_t geometry_id, uint32_t primitive,
                         float t, float b1, float b2, Hit* hit) const;

  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  ProjectiveCamera camera_;
  std::vector<RenderMaterial> materials_;
  RoughPlasticTables rough_plastic_tables_;  ///< one per distinct coating of the scene
  std::vector<std::unique_ptr<Geometry>> geometries_;  ///< indexed by Embree geometry id
  /// Per shape group: its Embree scene and its shapes' Geometry, indexed by geometry id there.
  std::vector<RTCScene> group_scenes_;
  std::vector<std::vector<std::unique_ptr<Geometry>>> group_geometries_;
  std::unique_ptr<TextureSet> textures_;
  std::unique_ptr<LightSet> lights_;
  SpecularTargets specular_targets_;
  CausticGuide caustic_guide_;
  float reach_ = 0;
  bool hide_emitters_ = false;
  int rr_depth_ = kDefaultRrDepth;
  std::vector<RenderMedium> media_;
  std::vector<glm::ivec2> medium_sides_;  ///< per top-level geometry; empty without media
  int32_t camera_medium_ = -1;
  bool has_media_ = false;
  std::string isa_;
  std::string device_error_;
  /// Whether anything reads a hit's uv, dpdu, dpdv (textures, anisotropic roughness).
  bool need_uv_ = false;
};

// Inlined into intersect() and make_hit(): a call per closest hit costs more than the hit record
// itself.
[[gnu::always_inline]] inline void TraceableScene::fill_triangle_hit(const Geometry& g, uint32_t primitive,
                                                                     float b1, float b2, Hit* hit) const {
  const glm::u32vec3 tri = g.indices[primitive];
  // References, not copies: GCC otherwise moves each vertex through the stack.
  const glm::vec3 &p0 = g.positions[tri.x], &p1 = g.positions[tri.y], &p2 = g.positions[tri.z];
  const float b0 = 1.0f - b1 - b2;
  hit->barycentric = {b1, b2};
  hit->sp.p = b0 * p0 + b1 * p1 + b2 * p2;
  hit->sp.p_error = glm::vec3(g.point_errors[primitive]);
  hit->sp.ng = g.face_normals[primitive];
  if (g.normals.empty()) {
    hit->ns = hit->sp.ng;
  } else {
    glm::vec3 ns = b0 * g.normals[tri.x] + b1 * g.normals[tri.y] + b2 * g.normals[tri.z];
    const float len = glm::length(ns);
    ns = len > 0 ? ns / len : hit->sp.ng;
    hit->ns = glm::dot(ns, hit->sp.ng) < 0 ? -ns : ns;
  }
  if (!need_uv_) return;
  const glm::vec3 e1 = p1 - p0, e2 = p2 - p0;
  if (g.uvs.empty()) {
    hit->uv = {b1, b2};
    hit->dpdu = e1;
    hit->dpdv = e2;
    return;
  }
  const glm::vec2 uv0 = g.uvs[tri.x], duv0 = g.uvs[tri.y] - uv0, duv1 = g.uvs[tri.z] - uv0;
  hit->uv = uv0 + b1 * duv0 + b2 * duv1;
  const float det = duv0.x * duv1.y - duv0.y * duv1.x;
  if (det != 0 && std::isfinite(1.0f / det)) {
    const float inv = 1.0f / det;
    hit->dpdu = (duv1.y * e1 - duv0.y * e2) * inv;
    hit->dpdv = (duv0.x * e2 - duv1.x * e1) * inv;
  } else {
    hit->dpdu = e1;
    hit->dpdv = e2;
  }
}

}  // namespace tessera
