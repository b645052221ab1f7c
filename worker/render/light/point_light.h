// Mitsuba's point emitter: an isotropic point source of radiant intensity.
#pragma once

#include <glm/vec3.hpp>

#include "render/light/light_sample.h"
#include "scene/scene.h"

namespace tessera {

class PointLight {
 public:
  /// light.kind == point: position = to_world's translation, value = intensity (W/sr).
  explicit PointLight(const Light& light);

  /// The light as seen from ref: radiance intensity / distance^2, pdf 1 (delta), or pdf 0 when
  /// ref is at the light's position.
  LightSample sample(glm::vec3 ref) const;
  /// Emitted power, luminance-weighted: 4 pi I.
  double power() const;

 private:
  glm::vec3 position_;
  glm::vec3 intensity_;
};

}  // namespace tessera
