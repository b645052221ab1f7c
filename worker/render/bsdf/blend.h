// Mitsuba 3's `blendbsdf`: (1 - weight) * first + weight * second, two nested BSDFs of any
// kind (blends nest too), the weight clamped to [0, 1] (src/bsdfs/blendbsdf.cpp).
#pragma once

#include <memory>
#include <optional>

#include <glm/vec2.hpp>

#include "render/bsdf/bsdf_sample.h"

namespace tessera {

class Bsdf;  // bsdf.h

class BlendBsdf {
 public:
  /// p.blend holds the two nested BSDFs' parameters, p.blend_weight the weight. Allocates the
  /// two nested BSDFs (the only BSDF that allocates: a blend can nest a blend).
  explicit BlendBsdf(const BsdfParams& p);
  ~BlendBsdf();
  BlendBsdf(BlendBsdf&&) noexcept;
  BlendBsdf& operator=(BlendBsdf&&) noexcept;

  glm::vec3 eval(glm::vec3 wo, glm::vec3 wi) const;
  float pdf(glm::vec3 wo, glm::vec3 wi) const;
  /// Chooses the second BSDF when u_lobe <= weight (u_lobe rescaled for it), as Mitsuba. Every
  /// sample gets Mitsuba's mixture weight (p f_chosen + (1 - p) f_other) / (p pdf_chosen +
  /// (1 - p) pdf_other), p the probability of the chosen BSDF. For a perfectly specular sample
  /// pdf_chosen is its lobe's probability and f_chosen = weight * that probability: Mitsuba
  /// mixes a probability with the other BSDF's density there, so a blend of a delta lobe with
  /// a smooth one reflects less than (1 - w) first + w second would; Tessera renders Mitsuba's
  /// images (docs/scenes.md, materials).
  std::optional<BsdfSample> sample(glm::vec3 wo, float u_lobe, glm::vec2 u) const;
  bool has_smooth_lobe() const;

 private:
  std::unique_ptr<Bsdf> first_, second_;
  float weight_;
};

}  // namespace tessera
