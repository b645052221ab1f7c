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
  /// Chooses the second BSDF when u_lobe <= weight (u_lobe rescaled for it), as Mitsuba. A
  /// smooth sample gets Mitsuba's mixture weight: (blended eval) / (blended pdf). A delta sample
  /// keeps its component's weight, with the probability of choosing that component in its pdf
  /// (the other component's density has no meaning on a delta direction).
  std::optional<BsdfSample> sample(glm::vec3 wo, float u_lobe, glm::vec2 u) const;
  bool has_smooth_lobe() const;

 private:
  std::unique_ptr<Bsdf> first_, second_;
  float weight_;
};

}  // namespace tessera
