// Mitsuba's spot emitter: a point source shining along its frame's +z, at full intensity inside
// beam_width, falling off linearly in angle to zero at cutoff_angle
// (mitsuba3 src/emitters/spot.cpp, falloff_curve).
#pragma once

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "render/light/light_sample.h"
#include "scene/scene.h"

namespace tessera {

class SpotLight {
 public:
  /// light.kind == spot: position and orientation from to_world (rigid), value = intensity at
  /// the centre (W/sr). Throws SceneError naming light.origin unless
  /// 0 < beam_width_deg <= cutoff_angle_deg <= 180.
  explicit SpotLight(const Light& light);

  /// The light as seen from ref: intensity * falloff / distance^2, pdf 1 (delta); pdf 0 outside
  /// the cone or at the light's position.
  LightSample sample(glm::vec3 ref) const;
  /// Mitsuba's falloff for a direction (in the light's frame, unit) whose z is cos_theta:
  /// 1 inside beam_width, (cutoff - theta) / (cutoff - beam_width) up to cutoff_angle, 0 beyond.
  float falloff(float cos_theta) const;
  /// Emitted power, luminance-weighted: I * 2 pi ((1 - cos beam) + (cos beam - cos cutoff) / 2)
  /// (pbrt-v4's SpotLight::Phi; exact for its smoothstep, close for the linear ramp).
  double power() const;

 private:
  glm::vec3 position_;
  glm::mat3 world_to_local_;
  glm::vec3 intensity_;
  float cutoff_rad_, beam_rad_;
  float cos_cutoff_, cos_beam_;
};

}  // namespace tessera
