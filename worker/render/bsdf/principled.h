// Mitsuba 3's `principled` BSDF: Burley's Disney BSDF as Mitsuba writes it (src/bsdfs/
// principled.cpp). Four lobes, weighted by metallic and spec_trans:
// - a diffuse lobe (Burley's diffuse with retro-reflection, blended towards a fake subsurface
//   lobe by flatness, plus sheen), weight (1 - metallic)(1 - spec_trans), front side only;
// - a GGX specular reflection (alpha from roughness and anisotropic) whose Fresnel term blends
//   the true dielectric one with Schlick terms tinted by base_color (metallic, spec_tint);
// - a GGX specular transmission through a boundary of index eta, weight
//   (1 - metallic) spec_trans, tinted by sqrt(base_color); both sides;
// - a GTR1 clear coat, weight clearcoat / 4, front side only.
// Seen from inside (wo.z < 0) only the untinted dielectric reflection and transmission remain.
// sample() chooses a lobe with Mitsuba's probabilities (main specular ∝ 1, clear coat ∝
// clearcoat / 4, diffuse ∝ its weight, each times its sampling rate; from inside reflection
// and transmission by the Fresnel term) and draws GGX visible normals, GTR1 normals or a
// cosine-distributed direction.
#pragma once

#include <optional>

#include <glm/vec2.hpp>

#include "render/bsdf/bsdf_sample.h"
#include "render/bsdf/microfacet.h"

namespace tessera {

class PrincipledBsdf {
 public:
  /// p.reflectance is base_color, p.eta the interior / exterior index, p.principled the rest.
  explicit PrincipledBsdf(const BsdfParams& p);
  /// f(wo, wi) |cos wi| (radiance transport; transmission includes the 1 / eta^2 factor);
  /// 0 when wo is perfectly grazing.
  glm::vec3 eval(glm::vec3 wo, glm::vec3 wi) const;
  float pdf(glm::vec3 wo, glm::vec3 wi) const;
  std::optional<BsdfSample> sample(glm::vec3 wo, float u_lobe, glm::vec2 u) const;
  bool has_smooth_lobe() const { return true; }
  /// The probability that sample() takes the diffuse lobe at wo, with the Fresnel reflectance
  /// of the macro-surface (sample() weighs the lobes by a sampled microfacet's); 0 below the
  /// surface.
  float diffuse_probability(glm::vec3 wo) const;

 private:
  /// The probabilities of choosing diffuse, clear coat, transmission and specular reflection
  /// for wo, given the dielectric Fresnel term f of the microfacet; they sum to 1.
  struct LobeChoice {
    float diffuse = 0, clearcoat = 0, transmission = 0, reflection = 0;
  };
  LobeChoice choose(float cos_theta_o, float f) const;
  /// The half vector of (wo, wi), pointing to the outside (+z).
  glm::vec3 half_vector(glm::vec3 wo, glm::vec3 wi) const;
  glm::vec3 fresnel_reflection(float f_dielectric, float cos_o_h, bool front) const;
  glm::vec3 diffuse_and_sheen(glm::vec3 wo, glm::vec3 wi, glm::vec3 h) const;

  PrincipledInputs in_;
  glm::vec3 base_color_;
  float eta_;
  float brdf_weight_, bsdf_weight_;  ///< (1 - metallic)(1 - spec_trans), (1 - metallic) spec_trans
  float luminance_;
  float clearcoat_alpha_;
  Microfacet distr_;
};

}  // namespace tessera
