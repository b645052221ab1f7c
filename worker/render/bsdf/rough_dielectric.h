// Mitsuba's `roughdielectric`: a rough boundary between two dielectrics (Walter et al. 2007),
// Beckmann or GGX, anisotropic alpha, seen from either side; reflects and transmits.
#pragma once

#include <optional>

#include <glm/vec2.hpp>

#include "render/bsdf/bsdf_sample.h"
#include "render/bsdf/microfacet.h"

namespace tessera {

class RoughDielectricBsdf {
 public:
  explicit RoughDielectricBsdf(const BsdfParams& p);
  glm::vec3 eval(glm::vec3 wo, glm::vec3 wi) const;
  float pdf(glm::vec3 wo, glm::vec3 wi) const;
  /// Draws a microfacet normal from wo's side, then reflects (u_lobe < F) or refracts.
  std::optional<BsdfSample> sample(glm::vec3 wo, float u_lobe, glm::vec2 u) const;
  bool has_smooth_lobe() const { return true; }

 private:
  /// The distribution sampled for wo: Walter's widened alpha when not sampling visible normals.
  Microfacet sampling_distribution(glm::vec3 wo) const;
  /// The half vector of (wo, wi) on the +z side, or nullopt when it is undefined.
  std::optional<glm::vec3> half_vector(glm::vec3 wo, glm::vec3 wi, bool reflect) const;

  Microfacet distr_;
  float eta_;
  glm::vec3 reflectance_, transmittance_;
};

}  // namespace tessera
