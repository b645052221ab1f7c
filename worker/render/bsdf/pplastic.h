// Mitsuba 3's `pplastic` as its RGB (non-polarized) variants render it (src/bsdfs/pplastic.cpp,
// the branch without Mueller matrices): a microfacet reflection F D G / (4 cos wo) of the
// coating, times specular_reflectance, plus a diffuse base seen through a smooth coating,
// diffuse_reflectance (1 - F(wo)) (1 - F(wi)) / pi. Unlike `roughplastic` there is no
// 1 / eta^2, no internal reflection between base and coating and no rough transmittance: its
// diffuse part is brighter. Anisotropic (alpha_u, alpha_v), one-sided.
#pragma once

#include <optional>

#include <glm/vec2.hpp>

#include "render/bsdf/bsdf_sample.h"
#include "render/bsdf/microfacet.h"

namespace tessera {

class PPlasticBsdf {
 public:
  /// p.reflectance = diffuse_reflectance, p.specular_reflectance, p.eta, p.distribution,
  /// p.alpha_u, p.alpha_v, p.sample_visible.
  explicit PPlasticBsdf(const BsdfParams& p);
  glm::vec3 eval(glm::vec3 wo, glm::vec3 wi) const;
  float pdf(glm::vec3 wo, glm::vec3 wi) const;
  /// The specular lobe with Mitsuba's fixed probability mean(specular) / (mean(diffuse) +
  /// mean(specular)) (0.5 when both are black), else a cosine-distributed direction; weight =
  /// eval / pdf of the mixture.
  std::optional<BsdfSample> sample(glm::vec3 wo, float u_lobe, glm::vec2 u) const;
  bool has_smooth_lobe() const { return true; }

 private:
  Microfacet distr_;
  glm::vec3 diffuse_reflectance_, specular_reflectance_;
  float eta_, specular_weight_;
};

}  // namespace tessera
