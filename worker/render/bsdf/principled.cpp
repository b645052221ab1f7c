#include "render/bsdf/principled.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "render/bsdf/fresnel.h"
#include "render/bsdf/principled_lobes.h"
#include "render/sampling/warp.h"

namespace tessera {
namespace {

using principled::facet_compatible;
using principled::lerp;
using principled::schlick;
using principled::schlick_weight;
using principled::specular_alphas;

/// The coat's shadowing alpha, fixed by Mitsuba.
constexpr float kClearcoatShadowingAlpha = 0.25f;

glm::vec3 flip_sign(glm::vec3 v, float s) { return std::signbit(s) ? -v : v; }

}  // namespace

PrincipledBsdf::PrincipledBsdf(const BsdfParams& p)
    : in_(p.principled),
      base_color_(p.reflectance),
      eta_(p.eta),
      brdf_weight_((1.0f - in_.metallic) * (1.0f - in_.spec_trans)),
      bsdf_weight_(in_.transmits ? (1.0f - in_.metallic) * in_.spec_trans : 0.0f),
      luminance_(principled::luminance(p.reflectance)),
      clearcoat_alpha_(lerp(0.1f, 0.001f, in_.clearcoat_gloss)),
      distr_(MicrofacetDistribution::ggx, specular_alphas(in_.roughness, in_.anisotropic).x,
             specular_alphas(in_.roughness, in_.anisotropic).y, /*sample_visible=*/true) {}

PrincipledBsdf::LobeChoice PrincipledBsdf::choose(float cos_theta_o, float f) const {
  const bool front = cos_theta_o > 0.0f;
  LobeChoice c;
  if (front) {
    c.reflection = in_.main_specular_sampling_rate * (1.0f - bsdf_weight_ * (1.0f - f));
    c.transmission = in_.transmits ? in_.main_specular_sampling_rate * bsdf_weight_ * (1.0f - f) : 0.0f;
    c.clearcoat = 0.25f * in_.clearcoat * in_.clearcoat_sampling_rate;
    c.diffuse = brdf_weight_ * in_.diffuse_reflectance_sampling_rate;
  } else {
    c.reflection = f;
    c.transmission = in_.transmits ? 1.0f - f : 0.0f;
  }
  const float total = c.reflection + c.transmission + c.clearcoat + c.diffuse;
  const float inv = total > 0.0f ? 1.0f / total : 0.0f;
  c.reflection *= inv;
  c.transmission *= inv;
  c.clearcoat *= inv;
  c.diffuse *= inv;
  return c;
}

glm::vec3 PrincipledBsdf::half_vector(glm::vec3 wo, glm::vec3 wi) const {
  const bool reflect = wo.z * wi.z > 0.0f;
  const float eta_path = wo.z > 0.0f ? eta_ : 1.0f / eta_;
  const glm::vec3 h = glm::normalize(wo + wi * (reflect ? 1.0f : eta_path));
  return flip_sign(h, h.z);
}

glm::vec3 PrincipledBsdf::fresnel_reflection(float f_dielectric, float cos_o_h, bool front) const {
  if (!front) return glm::vec3(bsdf_weight_ * f_dielectric);  // inside: untinted dielectric
  glm::vec3 f_schlick(0.0f);
  if (in_.metallic > 0.0f) f_schlick += in_.metallic * schlick(base_color_, cos_o_h, eta_);
  if (in_.spec_tint > 0.0f) {
    const float eta_it = cos_o_h >= 0.0f ? eta_ : 1.0f / eta_;
    const glm::vec3 tint = luminance_ > 0.0f ? base_color_ / luminance_ : glm::vec3(1.0f);
    f_schlick += (1.0f - in_.metallic) * in_.spec_tint *
                 schlick(tint * principled::schlick_r0(eta_it), cos_o_h, eta_);
  }
  return glm::vec3((1.0f - in_.metallic) * (1.0f - in_.spec_tint) * f_dielectric) + f_schlick;
}

glm::vec3 PrincipledBsdf::diffuse_and_sheen(glm::vec3 wo, glm::vec3 wi, glm::vec3 h) const {
  const float cos_o = std::abs(wo.z), cos_i = std::abs(wi.z);
  const float f_o = schlick_weight(cos_o), f_i = schlick_weight(cos_i);
  const float f_diff = (1.0f - 0.5f * f_o) * (1.0f - 0.5f * f_i);
  const float cos_d = glm::dot(h, wi);
  const float rr = 2.0f * in_.roughness * cos_d * cos_d;
  const float f_retro = rr * (f_i + f_o + f_i * f_o * (rr - 1.0f));
  float lobe = f_diff + f_retro;
  if (in_.flatness > 0.0f) {
    // Hanrahan-Krueger's fake subsurface, flattened by roughness as Burley's.
    const float fss90 = rr / 2.0f;
    const float fss = lerp(1.0f, fss90, f_i) * lerp(1.0f, fss90, f_o);
    const float f_ss = 1.25f * (fss * (1.0f / (cos_i + cos_o) - 0.5f) + 0.5f);
    lobe = lerp(lobe, f_ss, in_.flatness);
  }
  glm::vec3 value = brdf_weight_ * cos_i * base_color_ * (kInvPi * lobe);
  if (in_.sheen > 0.0f) {
    const float f_d = schlick_weight(std::abs(cos_d));
    glm::vec3 sheen_color(1.0f);
    if (in_.sheen_tint > 0.0f) {
      const glm::vec3 tint = luminance_ > 0.0f ? base_color_ / luminance_ : glm::vec3(1.0f);
      sheen_color = lerp(glm::vec3(1.0f), tint, in_.sheen_tint);
    }
    value += in_.sheen * (1.0f - in_.metallic) * f_d * cos_i * sheen_color;
  }
  return value;
}

glm::vec3 PrincipledBsdf::eval(glm::vec3 wo, glm::vec3 wi) const {
  const float cos_o = wo.z, cos_i = wi.z;
  if (cos_o == 0.0f) return glm::vec3(0.0f);
  const bool reflect = cos_o * cos_i > 0.0f, refract = cos_o * cos_i < 0.0f;
  const bool front = cos_o > 0.0f;
  const float eta_path = front ? eta_ : 1.0f / eta_;
  const glm::vec3 h = half_vector(wo, wi);
  const float dot_o = glm::dot(wo, h), dot_i = glm::dot(wi, h);
  const float f = fresnel_dielectric_signed(dot_o, eta_).r;
  const bool reflect_ok = reflect && facet_compatible(h, wo, wi, cos_o, true);
  const float d = distr_.eval(h), g = distr_.G(wo, wi, h);

  glm::vec3 value(0.0f);
  if (reflect_ok && f > 0.0f) {
    value += fresnel_reflection(f, dot_o, front) * (d * g / (4.0f * std::abs(cos_o)));
  }
  if (in_.transmits && bsdf_weight_ > 0.0f && refract && f < 1.0f &&
      facet_compatible(h, wo, wi, cos_o, false)) {
    // Radiance transport: the 1 / eta_path^2 compression cancels eta_path^2 of the Jacobian.
    const float denom = dot_o + eta_path * dot_i;
    const float t = std::abs((1.0f - f) * d * g * dot_o * dot_i / (cos_o * denom * denom));
    value += glm::sqrt(base_color_) * (bsdf_weight_ * t);
  }
  if (in_.clearcoat > 0.0f && reflect_ok && front) {
    const float f_cc = schlick(0.04f, dot_o, eta_);
    const float d_cc = principled::Gtr1(clearcoat_alpha_).eval(h);
    const float g_cc = principled::smith_ggx1(wo, h, kClearcoatShadowingAlpha) *
                       principled::smith_ggx1(wi, h, kClearcoatShadowingAlpha);
    // Mitsuba's clear coat has no 1 / (4 cos) factor: it is weighted as written there.
    value += glm::vec3(in_.clearcoat * 0.25f * f_cc * d_cc * g_cc * std::abs(cos_i));
  }
  if (brdf_weight_ > 0.0f && reflect && front) value += diffuse_and_sheen(wo, wi, h);
  return value;
}

float PrincipledBsdf::pdf(glm::vec3 wo, glm::vec3 wi) const {
  const float cos_o = wo.z, cos_i = wi.z;
  if (cos_o == 0.0f) return 0.0f;
  const bool reflect = cos_o * cos_i > 0.0f, refract = cos_o * cos_i < 0.0f;
  const float eta_path = cos_o > 0.0f ? eta_ : 1.0f / eta_;
  const glm::vec3 h = half_vector(wo, wi);
  const float dot_o = glm::dot(wo, h), dot_i = glm::dot(wi, h);
  const LobeChoice c = choose(cos_o, fresnel_dielectric_signed(dot_o, eta_).r);
  float dh_dwi;  // |d h / d wi|
  if (reflect || !in_.transmits) {
    dh_dwi = std::abs(1.0f / (4.0f * dot_i));
  } else {
    const float denom = dot_o + eta_path * dot_i;
    dh_dwi = std::abs(eta_path * eta_path * dot_i / (denom * denom));
  }
  const float facet_pdf = distr_.pdf(flip_sign(wo, cos_o), h);
  float pdf = 0.0f;
  const bool reflect_ok = reflect && facet_compatible(h, wo, wi, cos_o, true);
  if (reflect_ok) pdf += c.reflection * facet_pdf * dh_dwi;
  if (reflect) pdf += c.diffuse * cosine_hemisphere_pdf(cos_i);
  if (in_.transmits && refract && facet_compatible(h, wo, wi, cos_o, false)) {
    pdf += c.transmission * facet_pdf * dh_dwi;
  }
  if (c.clearcoat > 0.0f && reflect_ok) {
    pdf += c.clearcoat * principled::Gtr1(clearcoat_alpha_).pdf(h) * dh_dwi;
  }
  return pdf;
}

float PrincipledBsdf::diffuse_probability(glm::vec3 wo) const {
  if (!(wo.z > 0.0f)) return 0.0f;
  return choose(wo.z, fresnel_dielectric_signed(wo.z, eta_).r).diffuse;
}

std::optional<BsdfSample> PrincipledBsdf::sample(glm::vec3 wo, float u_lobe, glm::vec2 u) const {
  const float cos_o = wo.z;
  if (cos_o == 0.0f) return std::nullopt;
  const bool front = cos_o > 0.0f;
  if (!front && !(bsdf_weight_ > 0.0f)) return std::nullopt;
  const glm::vec3 m = distr_.sample(flip_sign(wo, cos_o), u).first;
  const DielectricFresnel fr = fresnel_dielectric_signed(glm::dot(wo, m), eta_);
  const LobeChoice c = choose(cos_o, fr.r);

  BsdfSample s;
  if (u_lobe < c.diffuse) {
    s.wi = square_to_cosine_hemisphere(u);
    if (!(cos_o * s.wi.z > 0.0f)) return std::nullopt;
  } else if (u_lobe < c.diffuse + c.clearcoat) {
    const glm::vec3 m_cc = principled::Gtr1(clearcoat_alpha_).sample(u);
    s.wi = reflect(wo, m_cc);
    if (!(cos_o * s.wi.z > 0.0f) || !facet_compatible(m_cc, wo, s.wi, cos_o, true)) {
      return std::nullopt;
    }
  } else if (u_lobe < c.diffuse + c.clearcoat + c.transmission) {
    s.wi = refract_m(wo, m, fr.cos_theta_t, fr.eta_ti);
    s.eta = fr.eta_it;
    if (!(cos_o * s.wi.z < 0.0f) || !facet_compatible(m, wo, s.wi, cos_o, false)) {
      return std::nullopt;
    }
  } else {
    s.wi = reflect(wo, m);
    if (!(cos_o * s.wi.z > 0.0f) || !facet_compatible(m, wo, s.wi, cos_o, true)) {
      return std::nullopt;
    }
  }
  s.pdf = pdf(wo, s.wi);
  if (!(s.pdf > 0.0f) || !std::isfinite(s.pdf)) return std::nullopt;
  s.weight = eval(wo, s.wi) / s.pdf;
  return s;
}

}  // namespace tessera
