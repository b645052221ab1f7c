// Mitsuba's `roughconductor`: a metal with Beckmann or GGX microfacets (Walter et al. 2007),
// anisotropic alpha, complex-index Fresnel per channel, one-sided.
#pragma once

#include <cmath>
#include <optional>

#include <glm/vec2.hpp>

#include "render/bsdf/bsdf_sample.h"
#include "render/bsdf/microfacet.h"

namespace tessera {

class RoughConductorBsdf {
 public:
  explicit RoughConductorBsdf(const BsdfParams& p);
  glm::vec3 eval(glm::vec3 wo, glm::vec3 wi) const;
  float pdf(glm::vec3 wo, glm::vec3 wi) const;
  std::optional<BsdfSample> sample(glm::vec3 wo, float u_lobe, glm::vec2 u) const;
  bool has_smooth_lobe() const { return true; }

  /// sqrt(alpha_u alpha_v): the lobe's width, for Bsdf::caustic_guide_share.
  float mean_alpha() const { return std::sqrt(distr_.alpha_u() * distr_.alpha_v()); }

 private:
  glm::vec3 fresnel(float cos_theta) const;

  Microfacet distr_;
  glm::vec3 specular_reflectance_, eta_, k_;
  bool perfect_;
};

}  // namespace tessera
