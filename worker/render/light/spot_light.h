// Mitsuba's spot emitter: a point source shining along its frame's +z, at full intensity inside
// beam_width, falling off linearly in angle to zero at cutoff_angle
// (mitsuba3 src/emitters/spot.cpp, falloff_curve), optionally through a texture projected over
// the cone (direction_to_uv there).
#pragma once

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "render/light/area_light.h"
#include "render/light/light_bounds.h"
#include "render/light/light_sample.h"
#include "scene/scene.h"

namespace tessera {

class SpotLight {
 public:
  /// light.kind == spot: position and orientation from to_world (rigid), value = intensity at
  /// the centre (W/sr), light.texture (when >= 0) looked up through `textures`, which must be
  /// safe to call from many threads. Throws SceneError naming light.origin unless
  /// 0 < beam_width_deg <= cutoff_angle_deg <= 180, or when a texture has no lookup.
  SpotLight(const Light& light, TextureLookup textures = {});

  /// The light as seen from ref: intensity * texture(uv(d)) * falloff / distance^2, pdf 1
  /// (delta); pdf 0 outside the cone or at the light's position.
  LightSample sample(glm::vec3 ref) const;
  /// Mitsuba's direction_to_uv: where direction `d` (in the light's frame, any length, z != 0)
  /// looks up the texture: 0.5 + 0.5 (d.x, d.y) / (d.z tan cutoff).
  glm::vec2 uv_of(glm::vec3 d) const;
  /// Mitsuba's falloff for a direction (in the light's frame, unit) whose z is cos_theta:
  /// 1 inside beam_width, (cutoff - theta) / (cutoff - beam_width) up to cutoff_angle, 0 beyond.
  float falloff(float cos_theta) const;
  /// Emitted power, luminance-weighted: I * 2 pi ((1 - cos beam) + (cos beam - cos cutoff) / 2)
  /// (pbrt-v4's SpotLight::Phi; exact for its smoothstep, close for the linear ramp), times
  /// the texture's mean luminance over the disc the cone covers (a 64 x 64 grid of lookups).
  /// Only the light picker uses it: an approximation changes noise, never the expected image.
  double power() const;
  /// What the light picker weighs it by (pbrt-v4's SpotLight::Bounds): a point light of its
  /// intensity (phi = 4 pi I, luminance, times the texture's mean, as power() has it) whose
  /// normals fill the beam (theta_o = beam_width) and which emits up to cutoff - beam_width
  /// beyond them, so that its importance is 0 only where the falloff is, and a dim light
  /// elsewhere in the scene cannot outweigh it inside its beam.
  LightBounds bounds() const;

 private:
  glm::vec3 position_;
  glm::mat3 world_to_local_;
  glm::vec3 intensity_;
  float cutoff_rad_, beam_rad_;
  float cos_cutoff_, cos_beam_;
  float uv_factor_;  ///< tan(cutoff)
  double disc_mean_luminance() const;
  int32_t texture_ = -1;
  TextureLookup textures_;
  double texture_mean_ = 1;  ///< see power()
};

}  // namespace tessera
