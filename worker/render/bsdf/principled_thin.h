// Mitsuba 3's `principledthin` BSDF: Burley's thin-surface extension of the Disney BSDF as
// Mitsuba writes it (src/bsdfs/principledthin.cpp), for sheets without thickness (leaves,
// paper, cloth). Four lobes, seen alike from both sides (the BSDF mirrors wo and wi to the
// front before evaluating):
// - a GGX specular reflection of weight spec_trans, whose Fresnel term (the dielectric one of
//   the sheet's eta) is tinted towards base_color by spec_tint through Schlick's form;
// - a GGX specular transmission of weight spec_trans, tinted by base_color, with the dielectric
//   (1 - F): the light is reflected about a microfacet and goes straight on through the sheet
//   (no bending), with the roughness scaled by (0.65 eta - 0.35) (Burley 2015, figure 15);
// - Burley's diffuse lobe with retro-reflection (blended towards a fake subsurface lobe by
//   flatness) and sheen (tinted by sheen_tint), of weight (1 - spec_trans)(1 - diff_trans / 2);
// - a Lambertian transmission of weight (1 - spec_trans) diff_trans / 2, tinted by base_color.
// sample() chooses a lobe with Mitsuba's probabilities (the two specular ones ∝ spec_trans / 2,
// diffuse reflection ∝ (1 - spec_trans)(1 - diff_trans / 2), diffuse transmission
// ∝ (1 - spec_trans) diff_trans / 2, each times its sampling rate), independent of direction.
// The path keeps its index: a sample's eta is 1.
#pragma once

#include <optional>

#include <glm/vec2.hpp>

#include "render/bsdf/bsdf_sample.h"
#include "render/bsdf/microfacet.h"

namespace tessera {

class PrincipledThinBsdf {
 public:
  /// p.reflectance is base_color, p.eta the sheet's index (> 0), p.principled the rest
  /// (roughness, anisotropic, spec_trans, spec_tint, sheen, sheen_tint, flatness, diff_trans and
  /// the four sampling rates; the weights are clamped to their ranges, [0, 1] and diff_trans
  /// [0, 2]).
  explicit PrincipledThinBsdf(const BsdfParams& p);
  /// f(wo, wi) |cos wi|; 0 when wo is perfectly grazing. Symmetric under flipping both sides.
  glm::vec3 eval(glm::vec3 wo, glm::vec3 wi) const;
  float pdf(glm::vec3 wo, glm::vec3 wi) const;
  std::optional<BsdfSample> sample(glm::vec3 wo, float u_lobe, glm::vec2 u) const;
  bool has_smooth_lobe() const { return true; }

 private:
  /// The probabilities of the four lobes; they sum to 1 (all 0 when every rate is 0).
  struct LobeChoice {
    float spec_reflect = 0, spec_trans = 0, diffuse_reflect = 0, diffuse_trans = 0;
  };
  LobeChoice choose() const;
  /// eval and pdf with wo on the front (wo.z > 0) and wi mirrored with it.
  glm::vec3 eval_front(glm::vec3 wo, glm::vec3 wi) const;
  float pdf_front(glm::vec3 wo, glm::vec3 wi) const;
  glm::vec3 diffuse_and_sheen(glm::vec3 wo, glm::vec3 wi, glm::vec3 h) const;

  PrincipledInputs in_;
  glm::vec3 base_color_;
  float eta_;
  float spec_trans_, diff_trans_;  ///< diff_trans_ is Mitsuba's diff_trans / 2, in [0, 1]
  Microfacet reflection_, transmission_;
};

}  // namespace tessera
