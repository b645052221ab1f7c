#include "render/bsdf/pplastic.h"

#include <cmath>

#include <glm/geometric.hpp>

#include "render/bsdf/fresnel.h"
#include "render/bsdf/plastic.h"
#include "render/sampling/warp.h"

namespace tessera {

PPlasticBsdf::PPlasticBsdf(const BsdfParams& p)
    : distr_(p.distribution, p.alpha_u, p.alpha_v, p.sample_visible),
      diffuse_reflectance_(p.reflectance),
      specular_reflectance_(p.specular_reflectance),
      eta_(p.eta),
      specular_weight_(plastic_specular_sampling_weight(p.reflectance, p.specular_reflectance)) {}

glm::vec3 PPlasticBsdf::eval(glm::vec3 wo, glm::vec3 wi) const {
  if (wo.z <= 0.0f || wi.z <= 0.0f) return glm::vec3(0.0f);
  const glm::vec3 h = glm::normalize(wo + wi);
  const float f = fresnel_dielectric_signed(glm::dot(wo, h), eta_).r;
  const float specular = f * distr_.eval(h) * distr_.G(wo, wi, h) / (4.0f * wo.z);
  const float f_o = fresnel_dielectric_signed(wo.z, eta_).r;
  const float f_i = fresnel_dielectric_signed(wi.z, eta_).r;
  return specular_reflectance_ * specular +
         diffuse_reflectance_ * ((1.0f - f_o) * (1.0f - f_i) * kInvPi * wi.z);
}

float PPlasticBsdf::pdf(glm::vec3 wo, glm::vec3 wi) const {
  if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
  const glm::vec3 h = glm::normalize(wo + wi);
  float specular = 0.0f;
  if (glm::dot(wo, h) > 0.0f && glm::dot(wi, h) > 0.0f) {
    specular = distr_.sample_visible()
                   ? distr_.eval(h) * distr_.smith_g1(wo, h) / (4.0f * wo.z)
                   : distr_.pdf(wo, h) / (4.0f * glm::dot(wi, h));
  }
  return specular_weight_ * specular + (1.0f - specular_weight_) * cosine_hemisphere_pdf(wi.z);
}

std::optional<BsdfSample> PPlasticBsdf::sample(glm::vec3 wo, float u_lobe, glm::vec2 u) const {
  if (wo.z <= 0.0f) return std::nullopt;
  BsdfSample s;
  if (u_lobe < specular_weight_) {
    s.wi = reflect(wo, distr_.sample(wo, u).first);
  } else {
    s.wi = square_to_cosine_hemisphere(u);
  }
  s.pdf = pdf(wo, s.wi);
  if (!(s.pdf > 0.0f) || !std::isfinite(s.pdf)) return std::nullopt;
  s.weight = eval(wo, s.wi) / s.pdf;
  return s;
}

}  // namespace tessera
