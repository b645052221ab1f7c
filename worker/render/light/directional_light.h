// Mitsuba's directional emitter: light arriving from infinitely far along one direction.
#pragma once

#include <glm/vec3.hpp>

#include "render/light/light_sample.h"
#include "scene/scene.h"

namespace tessera {

class DirectionalLight {
 public:
  /// light.kind == directional: light travels along to_world's +z; value = irradiance (W/m^2)
  /// on a surface facing it.
  explicit DirectionalLight(const Light& light);

  /// wi = the opposite of the travel direction, radiance = irradiance, distance +inf, pdf 1.
  LightSample sample() const;
  /// Power through the scene's bounding disc of radius `scene_radius`, luminance-weighted:
  /// pi r^2 E (pbrt-v4's DistantLight::Phi).
  double power(double scene_radius) const;

 private:
  glm::vec3 wi_;
  glm::vec3 irradiance_;
};

}  // namespace tessera
