// Mitsuba's `diffuse`: the Lambertian reflector, one-sided.
#pragma once

#include <optional>

#include <glm/vec2.hpp>

#include "render/bsdf/bsdf_sample.h"

namespace tessera {

class DiffuseBsdf {
 public:
  explicit DiffuseBsdf(const BsdfParams& p) : albedo_(p.reflectance) {}
  glm::vec3 eval(glm::vec3 wo, glm::vec3 wi) const;
  float pdf(glm::vec3 wo, glm::vec3 wi) const;
  std::optional<BsdfSample> sample(glm::vec3 wo, float u_lobe, glm::vec2 u) const;
  bool has_smooth_lobe() const { return true; }

 private:
  glm::vec3 albedo_;
};

}  // namespace tessera
