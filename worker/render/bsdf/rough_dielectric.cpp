#include "render/bsdf/rough_dielectric.h"

#include <cmath>

#include <glm/geometric.hpp>

#include "render/bsdf/fresnel.h"

namespace tessera {

RoughDielectricBsdf::RoughDielectricBsdf(const BsdfParams& p)
    : distr_(p.distribution, p.alpha_u, p.alpha_v, p.sample_visible),
      eta_(p.eta),
      reflectance_(p.specular_reflectance),
      transmittance_(p.specular_transmittance) {}

Microfacet RoughDielectricBsdf::sampling_distribution(glm::vec3 wo) const {
  Microfacet d = distr_;
  if (!d.sample_visible()) d.scale_alpha(1.2f - 0.2f * std::sqrt(std::abs(wo.z)));
  return d;
}

std::optional<glm::vec3> RoughDielectricBsdf::half_vector(glm::vec3 wo, glm::vec3 wi,
                                                          bool reflect) const {
  const float eta = wo.z > 0.0f ? eta_ : 1.0f / eta_;
  const glm::vec3 sum = wo + wi * (reflect ? 1.0f : eta);
  const float len2 = glm::dot(sum, sum);
  if (!(len2 > 0.0f)) return std::nullopt;
  glm::vec3 m = sum / std::sqrt(len2);
  if (m.z < 0.0f) m = -m;
  return m;
}

glm::vec3 RoughDielectricBsdf::eval(glm::vec3 wo, glm::vec3 wi) const {
  if (wo.z == 0.0f || wi.z == 0.0f) return glm::vec3(0.0f);
  const bool reflect = wo.z * wi.z > 0.0f;
  const auto m = half_vector(wo, wi, reflect);
  if (!m) return glm::vec3(0.0f);
  const float d = distr_.eval(*m);
  const float g = distr_.G(wo, wi, *m);
  if (d == 0.0f || g == 0.0f) return glm::vec3(0.0f);
  const float f = fresnel_dielectric_signed(glm::dot(wo, *m), eta_).r;
  if (reflect) return reflectance_ * (f * d * g / (4.0f * std::abs(wo.z)));
  const float eta = wo.z > 0.0f ? eta_ : 1.0f / eta_;
  const float wo_m = glm::dot(wo, *m), wi_m = glm::dot(wi, *m);
  const float denom = wo_m + eta * wi_m;
  if (denom == 0.0f) return glm::vec3(0.0f);
  // (1 / eta^2) is the radiance compression; eta^2 the Jacobian of the refracted half vector.
  const float value = (1.0f - f) * d * g * wo_m * wi_m / (wo.z * denom * denom);
  return transmittance_ * std::abs(value);
}

float RoughDielectricBsdf::pdf(glm::vec3 wo, glm::vec3 wi) const {
  if (wo.z == 0.0f || wi.z == 0.0f) return 0.0f;
  const bool reflect = wo.z * wi.z > 0.0f;
  const auto m = half_vector(wo, wi, reflect);
  if (!m) return 0.0f;
  const float wo_m = glm::dot(wo, *m), wi_m = glm::dot(wi, *m);
  // The micro and macro surfaces must agree on the side of each direction (as smith_g1).
  if (wo_m * wo.z <= 0.0f || wi_m * wi.z <= 0.0f) return 0.0f;
  const float eta = wo.z > 0.0f ? eta_ : 1.0f / eta_;
  float dwh_dwi;
  if (reflect) {
    dwh_dwi = 1.0f / (4.0f * wi_m);
  } else {
    const float denom = wo_m + eta * wi_m;
    if (denom == 0.0f) return 0.0f;
    dwh_dwi = eta * eta * wi_m / (denom * denom);
  }
  const Microfacet sd = sampling_distribution(wo);
  const glm::vec3 wo_up = wo.z > 0.0f ? wo : -wo;
  const float f = fresnel_dielectric_signed(wo_m, eta_).r;
  const float pdf = sd.pdf(wo_up, *m) * (reflect ? f : 1.0f - f) * std::abs(dwh_dwi);
  return std::isfinite(pdf) ? pdf : 0.0f;
}

std::optional<BsdfSample> RoughDielectricBsdf::sample(glm::vec3 wo, float u_lobe,
                                                      glm::vec2 u) const {
  if (wo.z == 0.0f) return std::nullopt;
  const Microfacet sd = sampling_distribution(wo);
  const glm::vec3 wo_up = wo.z > 0.0f ? wo : -wo;
  const auto [m, pdf_m] = sd.sample(wo_up, u);
  if (!(pdf_m > 0.0f)) return std::nullopt;
  const float wo_m = glm::dot(wo, m);
  // A normal that wo sees from behind (possible when sampling all normals) scatters nothing:
  // G is 0 there, and pdf() counts no density for it.
  if (wo_m * wo.z <= 0.0f) return std::nullopt;
  const DielectricFresnel f = fresnel_dielectric_signed(wo_m, eta_);
  BsdfSample s;
  glm::vec3 weight(1.0f);
  float dwh_dwi;
  if (u_lobe < f.r) {
    s.wi = reflect(wo, m);
    s.pdf = pdf_m * f.r;
    weight = reflectance_;
    dwh_dwi = 1.0f / (4.0f * glm::dot(s.wi, m));
    if (s.wi.z * wo.z <= 0.0f) return std::nullopt;
  } else {
    s.wi = refract_m(wo, m, f.cos_theta_t, f.eta_ti);
    s.pdf = pdf_m * (1.0f - f.r);
    s.eta = f.eta_it;
    weight = transmittance_ * (f.eta_ti * f.eta_ti);
    const float wi_m = glm::dot(s.wi, m);
    const float denom = wo_m + s.eta * wi_m;
    dwh_dwi = s.eta * s.eta * wi_m / (denom * denom);
    if (s.wi.z * wo.z >= 0.0f) return std::nullopt;
  }
  if (glm::dot(s.wi, m) * s.wi.z <= 0.0f) return std::nullopt;
  s.pdf *= std::abs(dwh_dwi);
  if (!(s.pdf > 0.0f) || !std::isfinite(s.pdf)) return std::nullopt;
  if (distr_.sample_visible()) {
    // D, G1(wo), F and the Jacobians cancel analytically against the density.
    s.weight = weight * distr_.smith_g1(s.wi, m);
  } else {
    // The widened sampling distribution does not cancel against D: divide. (Mitsuba's
    // shortcut G (wo.m) / (cos wo cos m) assumes it does, and is biased there.)
    s.weight = eval(wo, s.wi) / s.pdf;
  }
  return s;
}

}  // namespace tessera
