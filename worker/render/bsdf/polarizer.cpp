#include "render/bsdf/polarizer.h"

namespace tessera {

std::optional<BsdfSample> PolarizerBsdf::sample(glm::vec3 wo, float, glm::vec2) const {
  if (wo.z == 0.0f) return std::nullopt;
  BsdfSample s;
  s.delta = true;
  s.wi = -wo;
  s.pdf = 1.0f;
  s.eta = 1.0f;
  s.weight = 0.5f * transmittance_;  // unpolarized light through an ideal linear polarizer
  return s;
}

}  // namespace tessera
