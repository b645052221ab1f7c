#include "render/bsdf/principled_thin.h"

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
using principled::schlick_weight;
using principled::specular_alphas;

float clamp01(float x) { return std::isnan(x) ? 0.0f : std::clamp(x, 0.0f, 1.0f); }

Microfacet ggx(glm::vec2 alphas) {
  return Microfacet(MicrofacetDistribution::ggx, alphas.x, alphas.y, /*sample_visible=*/true);
}

/// Mitsuba's mulsign(v, s): v with the sign of s applied (s = -0 counts as negative).
glm::vec3 mulsign(glm::vec3 v, float s) { return std::signbit(s) ? -v : v; }

/// wi mirrored to the front of the surface: the microfacet lobes' reflection of a transmitted
/// direction, from which the half vector follows.
glm::vec3 mirrored_up(glm::vec3 wi) { return {wi.x, wi.y, std::abs(wi.z)}; }

}  // namespace

PrincipledThinBsdf::PrincipledThinBsdf(const BsdfParams& p)
    : in_(p.principled),
      base_color_(p.reflectance),
      eta_(p.eta),
      spec_trans_(clamp01(p.principled.spec_trans)),
      diff_trans_(clamp01(0.5f * p.principled.diff_trans)),
      reflection_(ggx(specular_alphas(clamp01(in_.roughness), clamp01(in_.anisotropic)))),
      // Burley 2015, figure 15: the transmission's roughness scaled by the sheet's index.
      transmission_(ggx(specular_alphas((0.65f * p.eta - 0.35f) * clamp01(in_.roughness),
                                        clamp01(in_.anisotropic)))) {
  in_.roughness = clamp01(in_.roughness);
  in_.spec_tint = clamp01(in_.spec_tint);
  in_.sheen = clamp01(in_.sheen);
  in_.sheen_tint = clamp01(in_.sheen_tint);
  in_.flatness = clamp01(in_.flatness);
}

PrincipledThinBsdf::LobeChoice PrincipledThinBsdf::choose() const {
  LobeChoice c;
  c.spec_reflect = spec_trans_ * in_.specular_reflectance_sampling_rate / 2.0f;
  c.spec_trans = spec_trans_ * in_.specular_transmittance_sampling_rate / 2.0f;
  c.diffuse_reflect =
      in_.diffuse_reflectance_sampling_rate * (1.0f - spec_trans_) * (1.0f - diff_trans_);
  c.diffuse_trans = in_.diffuse_transmittance_sampling_rate * (1.0f - spec_trans_) * diff_trans_;
  const float total = c.spec_reflect + c.spec_trans + c.diffuse_reflect + c.diffuse_trans;
  const float inv = total > 0.0f ? 1.0f / total : 0.0f;
  c.spec_reflect *= inv;
  c.spec_trans *= inv;
  c.diffuse_reflect *= inv;
  c.diffuse_trans *= inv;
  return c;
}

glm::vec3 PrincipledThinBsdf::diffuse_and_sheen(glm::vec3 wo, glm::vec3 wi, glm::vec3 h) const {
  const float cos_o = wo.z, cos_i = std::abs(wi.z);
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
  const float weight = (1.0f - spec_trans_) * (1.0f - diff_trans_);
  glm::vec3 value = weight * cos_i * base_color_ * (kInvPi * lobe);
  if (in_.sheen > 0.0f) {
    const glm::vec3 sheen_color =
        lerp(glm::vec3(1.0f), principled::tint_color(base_color_), in_.sheen_tint);
    value += in_.sheen * weight * schlick_weight(std::abs(cos_d)) * cos_i * sheen_color;
  }
  return value;
}

glm::vec3 PrincipledThinBsdf::eval_front(glm::vec3 wo, glm::vec3 wi) const {
  const float cos_o = wo.z, cos_i = wi.z;
  const bool reflect = cos_i > 0.0f, refract = cos_i < 0.0f;
  const glm::vec3 h = glm::normalize(wo + mirrored_up(wi));
  glm::vec3 value(0.0f);
  if (spec_trans_ > 0.0f) {
    const float dot_o = glm::dot(wo, h);
    const float f = fresnel_dielectric_signed(dot_o, eta_).r;
    if (reflect && facet_compatible(h, wo, wi, cos_o, true)) {
      glm::vec3 fresnel(f);
      if (in_.spec_tint > 0.0f) {
        const glm::vec3 r0 = principled::tint_color(base_color_) * principled::schlick_r0(eta_);
        fresnel = lerp(fresnel, principled::schlick(r0, dot_o, eta_), in_.spec_tint);
      }
      value += spec_trans_ * fresnel *
               (reflection_.eval(h) * reflection_.G(wo, wi, h) / (4.0f * cos_o));
    }
    if (refract && facet_compatible(h, wo, wi, cos_o, false)) {
      value += spec_trans_ * base_color_ *
               ((1.0f - f) * transmission_.eval(h) * transmission_.G(wo, wi, h) / (4.0f * cos_o));
    }
  }
  if (reflect && spec_trans_ < 1.0f && diff_trans_ < 1.0f) value += diffuse_and_sheen(wo, wi, h);
  if (refract && spec_trans_ < 1.0f && diff_trans_ > 0.0f) {
    value += (1.0f - spec_trans_) * diff_trans_ * base_color_ * (kInvPi * -cos_i);
  }
  return value;
}

float PrincipledThinBsdf::pdf_front(glm::vec3 wo, glm::vec3 wi) const {
  const LobeChoice c = choose();
  const bool reflect = wi.z > 0.0f, refract = wi.z < 0.0f;
  float pdf = 0.0f;
  if (spec_trans_ > 0.0f) {
    const glm::vec3 wi_up = mirrored_up(wi);
    const glm::vec3 h = glm::normalize(wo + wi_up);
    const float dh_dwi = std::abs(1.0f / (4.0f * glm::dot(wi_up, h)));
    if (reflect && facet_compatible(h, wo, wi, wo.z, true)) {
      pdf += c.spec_reflect * reflection_.pdf(wo, h) * dh_dwi;
    }
    if (refract && facet_compatible(h, wo, wi, wo.z, false)) {
      pdf += c.spec_trans * transmission_.pdf(wo, h) * dh_dwi;
    }
  }
  if (reflect) pdf += c.diffuse_reflect * cosine_hemisphere_pdf(wi.z);
  if (refract) pdf += c.diffuse_trans * cosine_hemisphere_pdf(-wi.z);
  return pdf;
}

glm::vec3 PrincipledThinBsdf::eval(glm::vec3 wo, glm::vec3 wi) const {
  if (wo.z == 0.0f) return glm::vec3(0.0f);
  return eval_front(mulsign(wo, wo.z), mulsign(wi, wo.z));
}

float PrincipledThinBsdf::pdf(glm::vec3 wo, glm::vec3 wi) const {
  if (wo.z == 0.0f) return 0.0f;
  return pdf_front(mulsign(wo, wo.z), mulsign(wi, wo.z));
}

std::optional<BsdfSample> PrincipledThinBsdf::sample(glm::vec3 wo, float u_lobe,
                                                     glm::vec2 u) const {
  if (wo.z == 0.0f) return std::nullopt;
  const glm::vec3 o = mulsign(wo, wo.z);
  const LobeChoice c = choose();
  glm::vec3 wi;
  if (u_lobe < c.spec_reflect) {
    const glm::vec3 m = reflection_.sample(o, u).first;
    wi = reflect(o, m);
    if (!(wi.z > 0.0f) || !facet_compatible(m, o, wi, o.z, true)) return std::nullopt;
  } else if (u_lobe < c.spec_reflect + c.spec_trans) {
    // Reflected about the microfacet, then straight through the sheet.
    const glm::vec3 m = transmission_.sample(o, u).first;
    wi = reflect(o, m);
    wi.z = -wi.z;
    if (!(wi.z < 0.0f) || !facet_compatible(m, o, wi, o.z, false)) return std::nullopt;
  } else if (u_lobe < c.spec_reflect + c.spec_trans + c.diffuse_reflect) {
    wi = square_to_cosine_hemisphere(u);
  } else if (c.diffuse_trans > 0.0f) {
    wi = -square_to_cosine_hemisphere(u);
  } else {
    return std::nullopt;
  }
  BsdfSample s;
  s.wi = mulsign(wi, wo.z);
  s.pdf = pdf_front(o, wi);
  if (!(s.pdf > 0.0f) || !std::isfinite(s.pdf)) return std::nullopt;
  s.weight = eval_front(o, wi) / s.pdf;
  return s;
}

}  // namespace tessera
