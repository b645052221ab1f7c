#include "render/bsdf/thin_dielectric.h"

#include <cmath>

#include "render/bsdf/fresnel.h"

namespace tessera {

float thin_sheet_reflectance(float cos_theta, float eta) {
  const float r = fresnel_dielectric_signed(cos_theta, eta).r;
  return r * (2.0f / (1.0f + r));  // the geometric series of reflections inside the sheet
}

std::optional<BsdfSample> ThinDielectricBsdf::sample(glm::vec3 wo, float u_lobe, glm::vec2) const {
  const float r = thin_sheet_reflectance(std::abs(wo.z), eta_);
  BsdfSample s;
  s.delta = true;
  if (u_lobe < r) {
    s.wi = reflect_z(wo);
    s.pdf = r;
    s.weight = reflectance_;
  } else {
    s.wi = -wo;
    s.pdf = 1.0f - r;
    s.weight = transmittance_;
  }
  if (!(s.pdf > 0.0f)) return std::nullopt;
  return s;
}

}  // namespace tessera
