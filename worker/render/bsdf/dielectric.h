// Mitsuba's `dielectric`: a smooth boundary between two dielectrics (glass, water), seen from
// either side; it reflects or refracts, choosing by the Fresnel reflectance.
#pragma once

#include <optional>

#include <glm/vec2.hpp>

#include "render/bsdf/bsdf_sample.h"

namespace tessera {

class DielectricBsdf {
 public:
  explicit DielectricBsdf(const BsdfParams& p)
      : eta_(p.eta),
        reflectance_(p.specular_reflectance),
        transmittance_(p.specular_transmittance) {}
  /// The same from the values themselves (path_vertex's untextured glass: no BsdfParams built).
  DielectricBsdf(float eta, glm::vec3 reflectance, glm::vec3 transmittance)
      : eta_(eta), reflectance_(reflectance), transmittance_(transmittance) {}
  /// Only delta lobes: eval and pdf are 0 for every pair of directions.
  glm::vec3 eval(glm::vec3, glm::vec3) const { return glm::vec3(0.0f); }
  float pdf(glm::vec3, glm::vec3) const { return 0.0f; }
  /// Reflection with probability R (u_lobe < R), refraction otherwise; u is unused.
  std::optional<BsdfSample> sample(glm::vec3 wo, float u_lobe, glm::vec2 u) const;
  bool has_smooth_lobe() const { return false; }

 private:
  float eta_;
  glm::vec3 reflectance_, transmittance_;
};

}  // namespace tessera
