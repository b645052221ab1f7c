// Mitsuba 3's `polarizer` as its RGB (non-polarized) variants render it (src/bsdfs/polarizer.cpp,
// the branch without Mueller matrices): an ideal linear polarizer seen by unpolarized light
// passes half of it, straight through and unchanged in direction, times `transmittance`, from
// either side. Nothing is reflected. Mitsuba flags it Null (a delta "pass through"); its path
// integrator samples it as a delta transmission of weight transmittance / 2 and does no light
// sampling at it, which is what a delta lobe gets here. theta and polarizing matter only to
// polarized variants: in RGB every angle gives the same image.
#pragma once

#include <optional>

#include <glm/vec2.hpp>

#include "render/bsdf/bsdf_sample.h"

namespace tessera {

class PolarizerBsdf {
 public:
  /// p.specular_transmittance = Mitsuba's transmittance (>= 0, per channel).
  explicit PolarizerBsdf(const BsdfParams& p) : transmittance_(p.specular_transmittance) {}
  /// Only a delta lobe: eval and pdf are 0 for every pair of directions.
  glm::vec3 eval(glm::vec3, glm::vec3) const { return glm::vec3(0.0f); }
  float pdf(glm::vec3, glm::vec3) const { return 0.0f; }
  /// wi = -wo with probability 1 (delta, eta 1), weight transmittance / 2; u_lobe and u unused.
  /// nullopt for a grazing wo (wo.z == 0), where no side is crossed.
  std::optional<BsdfSample> sample(glm::vec3 wo, float u_lobe, glm::vec2 u) const;
  bool has_smooth_lobe() const { return false; }

 private:
  glm::vec3 transmittance_;
};

}  // namespace tessera
