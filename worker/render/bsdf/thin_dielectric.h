// Mitsuba's `thindielectric`: a thin sheet of dielectric (a window pane). Light reflects off it
// with the sum of the inter-reflections between its two faces, R' = 2R / (1 + R), or passes
// straight through (no refraction: the two faces cancel), seen from either side.
#pragma once

#include <optional>

#include <glm/vec2.hpp>

#include "render/bsdf/bsdf_sample.h"

namespace tessera {

/// R' = 2R / (1 + R): the sheet's reflectance with the inter-reflections between its faces, at
/// |cos| = cos_theta for relative index eta (ThinDielectricBsdf's reflection probability; the
/// volumetric path tracer's null transmission through the sheet is 1 - R').
float thin_sheet_reflectance(float cos_theta, float eta);

class ThinDielectricBsdf {
 public:
  explicit ThinDielectricBsdf(const BsdfParams& p)
      : eta_(p.eta),
        reflectance_(p.specular_reflectance),
        transmittance_(p.specular_transmittance) {}
  /// Only delta lobes: eval and pdf are 0 for every pair of directions.
  glm::vec3 eval(glm::vec3, glm::vec3) const { return glm::vec3(0.0f); }
  float pdf(glm::vec3, glm::vec3) const { return 0.0f; }
  /// Reflection with probability R' (u_lobe < R'), straight transmission (wi = -wo) otherwise.
  std::optional<BsdfSample> sample(glm::vec3 wo, float u_lobe, glm::vec2 u) const;
  bool has_smooth_lobe() const { return false; }

 private:
  float eta_;
  glm::vec3 reflectance_, transmittance_;
};

}  // namespace tessera
