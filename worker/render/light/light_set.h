// Every light of a scene, as the integrator sees them: one sample per shading point, the
// radiance emitters send along rays that hit them or escape, and the densities MIS needs.
#pragma once

#include <cstdint>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <variant>
#include <vector>

#include "render/geometry/geometry.h"
#include "render/light/area_light.h"
#include "render/light/constant_light.h"
#include "render/light/directional_light.h"
#include "render/light/envmap_light.h"
#include "render/light/light_picker.h"
#include "render/light/light_sample.h"
#include "render/light/point_light.h"
#include "render/light/projector_light.h"
#include "render/light/spot_light.h"
#include "render/math/ray_offset.h"
#include "scene/file_reader.h"
#include "scene/scene.h"

namespace tessera {

class LightSet {
 public:
  /// Builds every light of the scene.
  /// - area_emitters: the Geometry of each emitting shape, in order, with
  ///   area_emitters[i]->emitter == i (as traceable_scene.cpp numbers them; std::invalid_argument
  ///   otherwise); each must outlive the set. Textured radiance (Geometry::emission_texture) is
  ///   looked up through `textures`, which must be safe to call from many threads.
  /// - lights: Scene::lights (point, spot, directional, constant, envmap, projector). Environment maps are
  ///   decoded from the bytes `reader` returns for Light::file.
  /// - scene_radius: radius of the geometry's bounding sphere; directional and environment
  ///   lights count with their power through a disc of that radius (divided by its square,
  ///   when lights are weighed at each point) when lights are picked.
  /// Throws SceneError naming the light's origin (and file) for a bad light: an environment map
  /// that cannot be decoded or holds NaN, infinite or negative texels, a spot light whose
  /// beam_width exceeds its cutoff_angle.
  LightSet(const std::vector<const Geometry*>& area_emitters, const std::vector<Light>& lights,
           const FileReader& reader, const TextureLookup& textures, float scene_radius);

  bool empty() const { return lights_.empty(); }
  /// Whether any light is at infinity in every direction (constant, envmap): escaping rays
  /// then carry light.
  bool has_environment() const { return !environment_.empty(); }

  /// One light sample for ref (point + geometric normal, which also steers the pick): picks a
  /// light (u_pick in [0,1); LightPicker: by importance at ref), then a point or direction on
  /// it (u in [0,1)^2). pdf == 0 means no contribution. An environment light's sample carries
  /// the radiance of every environment light along wi and their combined density
  /// (environment(), pdf_environment()), so that the same density weighs a BSDF-sampled ray
  /// escaping along wi. LightSample::pick_sum carries the picker's work at ref to pdf_area and
  /// pdf_environment.
  ///
  /// Inline, with area lights in line too (AreaLight::sample): the path vertex calls it for
  /// every diffuse hit, so it is built into each wavefront kernel's instruction set
  /// (docs/renderer.md, "Kernels per instruction set"); other lights go out of line.
  /// `importance`, when not null, holds every light's importance at ref, worked out ahead
  /// (LightPicker::pick): the same sample.
  [[gnu::always_inline]] LightSample sample(const SurfacePoint& ref, float u_pick, glm::vec2 u,
                                            const PointImportance* importance = nullptr) const {
    if (lights_.empty()) return {};
    float pick_pmf = 0, pick_sum = LightPicker::kUnknownSum;
    const uint32_t index = picker_.pick(u_pick, ref, &pick_pmf, &pick_sum, importance);
    if (index >= area_count_) return sample_other(index, pick_pmf, pick_sum, ref, u);
    LightSample s = std::get_if<AreaLight>(&lights_[index])->sample(ref.p, u);  // area lights first
    s.pdf *= pick_pmf;
    if (!(s.pdf > 0)) return {};
    s.pick_sum = pick_sum;
    return s;
  }

  /// The lights' importance where a light is picked per point (LightPicker), else null: for
  /// callers that evaluate it at many points at once and pass it to sample().
  const LightImportance* point_importance() const { return picker_.point_importance(); }

  /// Radiance leaving an emitting surface point of geometry g (primitive, uv; ng its
  /// front-facing unit geometric normal) towards w. 0 for a geometry that does not emit.
  glm::vec3 emitted(const Geometry& g, uint32_t primitive, glm::vec2 uv, glm::vec3 ng,
                    glm::vec3 w) const;

  /// Solid-angle pdf with which sample() from ref would have produced the point hit_p (normal
  /// hit_ng, either orientation) on area emitter g, pick probability included: for MIS when a
  /// BSDF-sampled ray hits it. 0 for a geometry that does not emit. `pick_sum`: the
  /// LightSample::pick_sum of a sample() from this very ref, so that the pick probability
  /// weighs one light instead of all (the same bits); negative (the default): not known.
  float pdf_area(const Geometry& g, uint32_t primitive, const SurfacePoint& ref, glm::vec3 hit_p,
                 glm::vec3 hit_ng, float pick_sum = LightPicker::kUnknownSum) const;

  /// Radiance of every environment light (constant + envmaps) along escaping direction d (unit).
  glm::vec3 environment(glm::vec3 d) const;
  /// The density sample() from ref gives direction d through the environment lights (pick
  /// probabilities at ref included): for MIS when a BSDF-sampled ray from ref escapes.
  /// `pick_sum` as for pdf_area.
  float pdf_environment(const SurfacePoint& ref, glm::vec3 d,
                        float pick_sum = LightPicker::kUnknownSum) const;

 private:
  using AnyLight =
      std::variant<AreaLight, PointLight, SpotLight, DirectionalLight, ConstantLight, EnvmapLight,
                   ProjectorLight>;

  /// sample() for light `index` (not an area light), picked with probability pick_pmf.
  LightSample sample_other(uint32_t index, float pick_pmf, float pick_sum, const SurfacePoint& ref,
                           glm::vec2 u) const;

  /// Solid-angle density of environment light i (constant or envmap) for direction d.
  float environment_pdf(uint32_t i, glm::vec3 d) const;

  std::vector<AnyLight> lights_;  ///< area lights first: lights_[i] is area emitter i
  uint32_t area_count_ = 0;
  std::vector<uint32_t> environment_;  ///< indices of constant and envmap lights
  LightPicker picker_;
};

}  // namespace tessera
