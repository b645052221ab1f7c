// Mitsuba's `roughplastic`: a diffuse base under a rough dielectric coating (Weidlich and
// Wilkie's layered model as Mitsuba writes it). The coating reflects with a microfacet lobe;
// the diffuse light is attenuated by the coating's rough transmittance on the way in and out,
// and scaled by 1 / (1 - R_int) (or 1 / (1 - albedo R_int) when `nonlinear`), R_int being the
// coating's internal hemispherical reflectance. Isotropic (alpha_u), one-sided.
#pragma once

#include <array>
#include <optional>

#include <glm/vec2.hpp>

#include "render/bsdf/bsdf_sample.h"
#include "render/bsdf/microfacet.h"

namespace tessera {

/// The Fresnel integrals of a rough dielectric coating, which depend only on the distribution,
/// alpha and eta: computed once per material with Mitsuba's quadrature.
struct RoughPlasticTable {
  static constexpr int kResolution = 64;  ///< Mitsuba's MI_ROUGH_TRANSMITTANCE_RES
  /// Rough transmittance into the coating for cos(theta) = i / (kResolution - 1).
  std::array<float, kResolution> external_transmittance{};
  /// Cosine-weighted hemispherical reflectance of the coating seen from inside.
  float internal_reflectance = 0;
  /// The parameters it was built for, checked by RoughPlasticBsdf.
  MicrofacetDistribution distribution = MicrofacetDistribution::beckmann;
  float alpha = 0, eta = 0;
};

/// Computes the table (a few tenths of a second: 64 directions times Gauss-Legendre grids of
/// 32^2 and 128^2 visible-normal samples, as Mitsuba's eval_transmittance / eval_reflectance).
RoughPlasticTable make_rough_plastic_table(MicrofacetDistribution distribution, float alpha,
                                           float eta);

class RoughPlasticBsdf {
 public:
  /// Requires p.rough_plastic, built for p's distribution, alpha_u and eta; throws
  /// std::invalid_argument otherwise.
  explicit RoughPlasticBsdf(const BsdfParams& p);
  glm::vec3 eval(glm::vec3 wo, glm::vec3 wi) const;
  float pdf(glm::vec3 wo, glm::vec3 wi) const;
  /// The specular lobe with probability proportional to (1 - T(wo)) times the mean specular
  /// reflectance, else a cosine-distributed direction; weight = eval / pdf of the mixture.
  std::optional<BsdfSample> sample(glm::vec3 wo, float u_lobe, glm::vec2 u) const;
  bool has_smooth_lobe() const { return true; }
  /// The probability that sample() takes the diffuse lobe at wo (0 below the surface).
  float diffuse_probability(glm::vec3 wo) const;

 private:
  float transmittance(float cos_theta) const;
  float specular_probability(float t_o) const;

  Microfacet distr_;
  glm::vec3 diffuse_reflectance_, specular_reflectance_;
  float eta_, inv_eta2_, specular_weight_;
  bool nonlinear_;
  const RoughPlasticTable* table_;
};

}  // namespace tessera
