#include "render/bsdf/dielectric.h"

#include "render/bsdf/fresnel.h"

namespace tessera {

std::optional<BsdfSample> DielectricBsdf::sample(glm::vec3 wo, float u_lobe, glm::vec2) const {
  const DielectricFresnel f = fresnel_dielectric_signed(wo.z, eta_);
  BsdfSample s;
  s.delta = true;
  if (u_lobe < f.r) {
    s.wi = reflect_z(wo);
    s.pdf = f.r;
    s.weight = reflectance_;
  } else {
    s.wi = refract_z(wo, f.cos_theta_t, f.eta_ti);
    s.pdf = 1.0f - f.r;
    // Radiance is compressed into the smaller solid angle of the denser side.
    s.weight = transmittance_ * (f.eta_ti * f.eta_ti);
    s.eta = f.eta_it;
  }
  if (!(s.pdf > 0.0f)) return std::nullopt;
  return s;
}

}  // namespace tessera
