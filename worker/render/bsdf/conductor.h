// Mitsuba's `conductor` (and Tessera's `mirror`, a perfect conductor): a smooth metal that
// reflects wo about the normal with the complex-index Fresnel reflectance, one-sided.
#pragma once

#include <optional>

#include <glm/vec2.hpp>

#include "render/bsdf/bsdf_sample.h"

namespace tessera {

class ConductorBsdf {
 public:
  explicit ConductorBsdf(const BsdfParams& p);
  /// The same from the values themselves (path_vertex's untextured mirrors and conductors: no
  /// BsdfParams built); `perfect`: no Fresnel factor (a mirror).
  ConductorBsdf(glm::vec3 specular_reflectance, glm::vec3 eta, glm::vec3 k, bool perfect)
      : specular_reflectance_(specular_reflectance), eta_(eta), k_(k), perfect_(perfect) {}
  /// Only a delta lobe: eval and pdf are 0 for every pair of directions.
  glm::vec3 eval(glm::vec3, glm::vec3) const { return glm::vec3(0.0f); }
  float pdf(glm::vec3, glm::vec3) const { return 0.0f; }
  std::optional<BsdfSample> sample(glm::vec3 wo, float u_lobe, glm::vec2 u) const;
  bool has_smooth_lobe() const { return false; }

 private:
  glm::vec3 specular_reflectance_, eta_, k_;
  bool perfect_;
};

}  // namespace tessera
