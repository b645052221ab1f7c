#include "render/bsdf/plastic.h"

#include "render/bsdf/fresnel.h"
#include "render/sampling/warp.h"

namespace tessera {

float plastic_specular_sampling_weight(glm::vec3 diffuse_reflectance,
                                       glm::vec3 specular_reflectance) {
  const float d = (diffuse_reflectance.x + diffuse_reflectance.y + diffuse_reflectance.z) / 3.0f;
  const float s = (specular_reflectance.x + specular_reflectance.y + specular_reflectance.z) / 3.0f;
  return d + s > 0.0f ? s / (d + s) : 0.5f;
}

float plastic_internal_reflectance(float eta) {
  if (eta <= 2.0f) return fresnel_diffuse_reflectance(1.0f / eta);
  // Beyond the fit's range (it exceeds 1 near eta = 4): the exact relation between the
  // hemispherical reflectances of the two sides, 1 - R_int = (1 - R_ext) / eta^2, with the
  // exterior fit that stays accurate up to eta = 10.
  return 1.0f - (1.0f - fresnel_diffuse_reflectance(eta)) / (eta * eta);
}

PlasticBsdf::PlasticBsdf(const BsdfParams& p)
    : diffuse_reflectance_(p.reflectance),
      specular_reflectance_(p.specular_reflectance),
      eta_(p.eta),
      inv_eta2_(1.0f / (p.eta * p.eta)),
      fdr_int_(plastic_internal_reflectance(p.eta)),
      specular_weight_(plastic_specular_sampling_weight(p.reflectance, p.specular_reflectance)),
      nonlinear_(p.nonlinear) {}

float PlasticBsdf::specular_probability(float f_o) const {
  const float spec = f_o * specular_weight_, diff = (1.0f - f_o) * (1.0f - specular_weight_);
  return spec + diff > 0.0f ? spec / (spec + diff) : 0.0f;
}

float PlasticBsdf::diffuse_probability(glm::vec3 wo) const {
  if (wo.z <= 0.0f) return 0.0f;
  return 1.0f - specular_probability(fresnel_dielectric_signed(wo.z, eta_).r);
}

glm::vec3 PlasticBsdf::diffuse(float f_o, float f_i) const {
  glm::vec3 diff = diffuse_reflectance_;
  diff /= glm::vec3(1.0f) - (nonlinear_ ? diff * fdr_int_ : glm::vec3(fdr_int_));
  return diff * (inv_eta2_ * (1.0f - f_o) * (1.0f - f_i));
}

glm::vec3 PlasticBsdf::eval(glm::vec3 wo, glm::vec3 wi) const {
  if (wo.z <= 0.0f || wi.z <= 0.0f) return glm::vec3(0.0f);
  const float f_o = fresnel_dielectric_signed(wo.z, eta_).r;
  const float f_i = fresnel_dielectric_signed(wi.z, eta_).r;
  return diffuse(f_o, f_i) * cosine_hemisphere_pdf(wi.z);
}

float PlasticBsdf::pdf(glm::vec3 wo, glm::vec3 wi) const {
  if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
  const float f_o = fresnel_dielectric_signed(wo.z, eta_).r;
  return cosine_hemisphere_pdf(wi.z) * (1.0f - specular_probability(f_o));
}

std::optional<BsdfSample> PlasticBsdf::sample(glm::vec3 wo, float u_lobe, glm::vec2 u) const {
  if (wo.z <= 0.0f) return std::nullopt;
  const float f_o = fresnel_dielectric_signed(wo.z, eta_).r;
  const float p_spec = specular_probability(f_o);
  BsdfSample s;
  if (u_lobe < p_spec) {
    s.wi = reflect_z(wo);
    s.pdf = p_spec;
    s.delta = true;
    s.weight = specular_reflectance_ * (f_o / p_spec);
    return s;
  }
  s.wi = square_to_cosine_hemisphere(u);
  const float p_diff = 1.0f - p_spec;
  s.pdf = p_diff * cosine_hemisphere_pdf(s.wi.z);
  if (!(s.pdf > 0.0f)) return std::nullopt;
  const float f_i = fresnel_dielectric_signed(s.wi.z, eta_).r;
  s.weight = diffuse(f_o, f_i) / p_diff;
  return s;
}

}  // namespace tessera
