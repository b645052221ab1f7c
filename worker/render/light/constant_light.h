// Mitsuba's constant emitter: the same radiance from every direction of the sphere.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "scene/scene.h"

namespace tessera {

class ConstantLight {
 public:
  /// light.kind == constant: value = radiance (W/(m^2 sr)).
  explicit ConstantLight(const Light& light);

  glm::vec3 radiance() const { return radiance_; }
  /// A uniformly distributed direction on the sphere from u in [0,1)^2 (as Mitsuba samples it);
  /// `pdf` receives its solid-angle density 1 / (4 pi).
  glm::vec3 sample(glm::vec2 u, float* pdf) const;
  float pdf() const;
  /// Power through the scene's bounding disc, luminance-weighted: pi r^2 * 4 pi L
  /// (pbrt-v4's UniformInfiniteLight::Phi).
  double power(double scene_radius) const;

 private:
  glm::vec3 radiance_;
};

}  // namespace tessera
