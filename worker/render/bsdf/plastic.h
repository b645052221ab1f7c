// Mitsuba's `plastic`: a diffuse base under a smooth dielectric coating. The coating reflects
// specularly with the Fresnel reflectance; light refracted into it scatters diffusely, bounces
// between base and coating (the internal-scattering factor 1 / (1 - Fdr), or 1 / (1 - albedo
// Fdr) when `nonlinear`) and leaves through the coating. One-sided.
#pragma once

#include <optional>

#include <glm/vec2.hpp>

#include "render/bsdf/bsdf_sample.h"

namespace tessera {

class PlasticBsdf {
 public:
  explicit PlasticBsdf(const BsdfParams& p);
  /// The diffuse lobe only (the specular one is a delta).
  glm::vec3 eval(glm::vec3 wo, glm::vec3 wi) const;
  /// The density of the diffuse lobe times the probability of choosing it.
  float pdf(glm::vec3 wo, glm::vec3 wi) const;
  /// The specular reflection (delta) with probability proportional to F(wo) times the mean
  /// specular reflectance, else a cosine-distributed diffuse direction.
  std::optional<BsdfSample> sample(glm::vec3 wo, float u_lobe, glm::vec2 u) const;
  bool has_smooth_lobe() const { return true; }
  /// The probability that sample() takes the diffuse lobe at wo (0 below the surface).
  float diffuse_probability(glm::vec3 wo) const;

 private:
  float specular_probability(float f_o) const;
  glm::vec3 diffuse(float f_o, float f_i) const;

  glm::vec3 diffuse_reflectance_, specular_reflectance_;
  float eta_, inv_eta2_, fdr_int_, specular_weight_;
  bool nonlinear_;
};

/// The coating's hemispherical reflectance seen from inside, for interior / exterior index eta:
/// Mitsuba's fit fresnel_diffuse_reflectance(1 / eta) up to eta = 2 (the plastics' usual
/// range, where it is accurate to 0.6 %), the reciprocity relation with the exterior fit above.
float plastic_internal_reflectance(float eta);

/// Mitsuba's steering of samples between the specular and diffuse lobes of the plastics:
/// mean(specular) / (mean(diffuse) + mean(specular)); 0.5 when both are black.
float plastic_specular_sampling_weight(glm::vec3 diffuse_reflectance,
                                       glm::vec3 specular_reflectance);

}  // namespace tessera
