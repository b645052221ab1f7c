#include "render/bsdf/rough_conductor.h"

#include <glm/geometric.hpp>

#include "render/bsdf/fresnel.h"

namespace tessera {

RoughConductorBsdf::RoughConductorBsdf(const BsdfParams& p)
    : distr_(p.distribution, p.alpha_u, p.alpha_v, p.sample_visible),
      specular_reflectance_(p.specular_reflectance),
      eta_(p.conductor_eta),
      k_(p.conductor_k),
      perfect_(p.perfect) {}

glm::vec3 RoughConductorBsdf::fresnel(float cos_theta) const {
  return perfect_ ? glm::vec3(1.0f) : fresnel_conductor(cos_theta, eta_, k_);
}

glm::vec3 RoughConductorBsdf::eval(glm::vec3 wo, glm::vec3 wi) const {
  if (wo.z <= 0.0f || wi.z <= 0.0f) return glm::vec3(0.0f);
  const glm::vec3 h = glm::normalize(wo + wi);
  const float d = distr_.eval(h);
  if (d == 0.0f) return glm::vec3(0.0f);
  const float value = d * distr_.G(wo, wi, h) / (4.0f * wo.z);
  return specular_reflectance_ * fresnel(glm::dot(wo, h)) * value;
}

float RoughConductorBsdf::pdf(glm::vec3 wo, glm::vec3 wi) const {
  if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
  const glm::vec3 h = glm::normalize(wo + wi);
  if (glm::dot(wo, h) <= 0.0f || glm::dot(wi, h) <= 0.0f) return 0.0f;
  if (distr_.sample_visible()) return distr_.eval(h) * distr_.smith_g1(wo, h) / (4.0f * wo.z);
  return distr_.pdf(wo, h) / (4.0f * glm::dot(wi, h));
}

std::optional<BsdfSample> RoughConductorBsdf::sample(glm::vec3 wo, float, glm::vec2 u) const {
  if (wo.z <= 0.0f) return std::nullopt;
  const auto [m, pdf_m] = distr_.sample(wo, u);
  BsdfSample s;
  s.wi = reflect(wo, m);
  const float wi_m = glm::dot(s.wi, m);
  if (!(pdf_m > 0.0f) || s.wi.z <= 0.0f || !(wi_m > 0.0f)) return std::nullopt;
  // The terms of f cos / pdf that do not cancel analytically.
  const float g = distr_.sample_visible() ? distr_.smith_g1(s.wi, m)
                                          : distr_.G(wo, s.wi, m) * glm::dot(wo, m) / (wo.z * m.z);
  s.pdf = pdf_m / (4.0f * wi_m);
  s.weight = specular_reflectance_ * fresnel(glm::dot(wo, m)) * g;
  return s;
}

}  // namespace tessera
