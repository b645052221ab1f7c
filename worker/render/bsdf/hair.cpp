#include "render/bsdf/hair.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "render/bsdf/fresnel.h"
#include "render/sampling/warp.h"

namespace tessera {
namespace {

constexpr float kTwoPi = 6.28318530717958647692f;

float safe_sqrt(float x) { return std::sqrt(std::max(x, 0.0f)); }
float safe_asin(float x) { return std::asin(std::clamp(x, -1.0f, 1.0f)); }
float safe_acos(float x) { return std::acos(std::clamp(x, -1.0f, 1.0f)); }

/// Mitsuba's luminance of linear sRGB.
float luminance(glm::vec3 c) { return 0.212671f * c.x + 0.715160f * c.y + 0.072169f * c.z; }

/// The modified Bessel function I0 by its series (Mitsuba's warp::detail::i0), and its log.
float i0(float x) {
  float result = 1, x2 = x * x, xi = x2, denom = 4;
  for (int i = 1; i <= 10; ++i) {
    const float factor = float(i) + 1.0f;
    result += xi / denom;
    xi *= x2;
    denom *= 4.0f * factor * factor;
  }
  return result;
}
float log_i0(float x) {
  return x > 12 ? x + 0.5f * (std::log(1.0f / (kTwoPi * x)) + 1.0f / (8.0f * x)) : std::log(i0(x));
}

}  // namespace

float hair_longitudinal(glm::vec3 wi_p, glm::vec3 wo, float v) {
  const float kappa = 1.0f / v;
  const float sin_i = wi_p.y, sin_o = wo.y;
  const float cos_i = safe_sqrt(1 - sin_i * sin_i), cos_o = safe_sqrt(1 - sin_o * sin_o);
  const float c = cos_i * cos_o * kappa, s = sin_i * sin_o * kappa;
  if (kappa > 10) {
    return std::exp(-s + log_i0(c) - kappa + 0.6931f + std::log(0.5f * kappa)) * (1 / kTwoPi);
  }
  return std::exp(-s) * i0(c) * kappa / (2.0f * std::sinh(kappa)) * (1 / kTwoPi);
}

namespace {

float logistic(float x, float s) {
  x = std::abs(x);
  const float e = std::exp(-x / s);
  return e / (s * (1 + e) * (1 + e));
}
float logistic_cdf(float x, float s) { return 1.0f / (1.0f + std::exp(-x / s)); }

float trimmed_logistic_sample(float u, float s) {
  const float k = logistic_cdf(kPi, s) - logistic_cdf(-kPi, s);
  const float x = -s * std::log(1.0f / (u * k + logistic_cdf(-kPi, s)) - 1.0f);
  return std::clamp(x, -kPi, kPi);
}

/// N_p: the trimmed logistic around the perfectly specular azimuth of path length p.
float azimuthal(float delta_phi, int p, float s, float gamma_o, float gamma_t) {
  const float perfect = 2 * float(p) * gamma_t - 2 * gamma_o + float(p) * kPi;
  float phi = std::fmod(delta_phi - perfect, kTwoPi);
  if (phi < kPi) phi += kTwoPi;
  if (phi > kPi) phi -= kTwoPi;
  return logistic(phi, s) / (logistic_cdf(kPi, s) - logistic_cdf(-kPi, s));
}

/// The angle in the fibre's cross-section between the normal and w (its offset h = sin gamma).
float gamma_of(glm::vec3 w) {
  const float proj = safe_sqrt(w.x * w.x + w.z * w.z);
  const float g = proj == 0 ? 0.0f : safe_acos(w.z / proj);
  return w.x < 0 ? g : -g;
}

}  // namespace

HairBsdf::HairBsdf(const HairInputs& p) : sigma_a_(p.sigma_a), eta_(p.eta) {
  sin_2k_alpha_[0] = std::sin(p.scale_tilt_deg * (kPi / 180.0f));
  cos_2k_alpha_[0] = safe_sqrt(1 - sin_2k_alpha_[0] * sin_2k_alpha_[0]);
  for (int i = 1; i < 3; ++i) {
    sin_2k_alpha_[i] = 2 * cos_2k_alpha_[i - 1] * sin_2k_alpha_[i - 1];
    const float s = sin_2k_alpha_[i - 1], c = cos_2k_alpha_[i - 1];
    cos_2k_alpha_[i] = c * c - s * s;
  }
  const float bn = p.azimuthal_roughness, bm = p.longitudinal_roughness;
  s_ = std::sqrt(kPi / 8.0f) * (0.265f * bn + 1.194f * bn * bn + 5.372f * std::pow(bn, 22.0f));
  const float v0 = 0.726f * bm + 0.812f * bm * bm + 3.7f * std::pow(bm, 20.0f);
  v_[0] = v0 * v0;
  v_[1] = 0.25f * v_[0];
  v_[2] = 4 * v_[0];
  v_[3] = v_[2];
}

void HairBsdf::reframe(float sin_theta, float cos_theta, int p, float* sin_p, float* cos_p) const {
  switch (p) {
    case 0:
      *sin_p = sin_theta * cos_2k_alpha_[1] - cos_theta * sin_2k_alpha_[1];
      *cos_p = cos_theta * cos_2k_alpha_[1] + sin_theta * sin_2k_alpha_[1];
      break;
    case 1:
      *sin_p = sin_theta * cos_2k_alpha_[0] + cos_theta * sin_2k_alpha_[0];
      *cos_p = cos_theta * cos_2k_alpha_[0] - sin_theta * sin_2k_alpha_[0];
      break;
    case 2:
      *sin_p = sin_theta * cos_2k_alpha_[2] + cos_theta * sin_2k_alpha_[2];
      *cos_p = cos_theta * cos_2k_alpha_[2] - sin_theta * sin_2k_alpha_[2];
      break;
    default:
      *sin_p = sin_theta;
      *cos_p = cos_theta;
  }
  *cos_p = std::abs(*cos_p);
}

void HairBsdf::attenuation(float cos_theta_o, float h, glm::vec3 transmittance,
                           glm::vec3 a_p[kPMax + 1]) const {
  const float cos_gamma = safe_sqrt(1 - h * h);
  float cos_t = 0;
  const float f = fresnel_dielectric(cos_theta_o * cos_gamma, eta_, &cos_t);
  a_p[0] = glm::vec3(f);
  a_p[1] = (1 - f) * (1 - f) * transmittance;
  for (int p = 2; p < kPMax; ++p) a_p[p] = a_p[p - 1] * transmittance * f;
  a_p[kPMax] = a_p[kPMax - 1] * f * transmittance / (1.0f - transmittance * f);
}

void HairBsdf::attenuation_pdf(glm::vec3 wo, float pdf[kPMax + 1]) const {
  const float h = std::sin(gamma_of(wo));
  const float sin_theta = wo.y, cos_theta = safe_sqrt(1 - sin_theta * sin_theta);
  const float sin_theta_t = sin_theta / eta_;
  const float cos_theta_t = safe_sqrt(1 - sin_theta_t * sin_theta_t);
  const float eta_p = safe_sqrt(eta_ * eta_ - sin_theta * sin_theta) / cos_theta;
  const float sin_gamma_t = h / eta_p, cos_gamma_t = safe_sqrt(1 - sin_gamma_t * sin_gamma_t);
  const glm::vec3 transmittance = glm::exp(-sigma_a_ * (2 * cos_gamma_t / cos_theta_t));
  glm::vec3 a_p[kPMax + 1];
  attenuation(cos_theta, h, transmittance, a_p);
  float sum = 0;
  for (int p = 0; p <= kPMax; ++p) sum += (pdf[p] = luminance(a_p[p]));
  for (int p = 0; p <= kPMax; ++p) pdf[p] /= sum;
}

void HairBsdf::eval_pdf(glm::vec3 wo, glm::vec3 wi, glm::vec3* value, float* pdf) const {
  // Mitsuba's si.wi is wo here and its wo is wi.
  const float gamma_o = gamma_of(wo), h = std::sin(gamma_o);
  const float sin_theta_o = wo.y, cos_theta_o = safe_sqrt(1 - sin_theta_o * sin_theta_o);
  const float phi_o = std::atan2(wo.z, wo.x), phi_i = std::atan2(wi.z, wi.x);
  const float sin_phi_o = std::sin(phi_o), cos_phi_o = std::cos(phi_o);
  const float sin_theta_t = sin_theta_o / eta_;
  const float cos_theta_t = safe_sqrt(1 - sin_theta_t * sin_theta_t);
  const float eta_p = safe_sqrt(eta_ * eta_ - sin_theta_o * sin_theta_o) / cos_theta_o;
  const float sin_gamma_t = h / eta_p, cos_gamma_t = safe_sqrt(1 - sin_gamma_t * sin_gamma_t);
  const float gamma_t = safe_asin(sin_gamma_t);
  const glm::vec3 transmittance = glm::exp(-sigma_a_ * (2 * cos_gamma_t / cos_theta_t));
  glm::vec3 a_p[kPMax + 1];
  attenuation(cos_theta_o, h, transmittance, a_p);
  float a_pdf[kPMax + 1];
  if (pdf) attenuation_pdf(wo, a_pdf);
  const float delta_phi = phi_i - phi_o;
  glm::vec3 f(0.0f);
  float density = 0;
  for (int p = 0; p < kPMax; ++p) {
    float sin_p = 0, cos_p = 0;
    reframe(sin_theta_o, cos_theta_o, p, &sin_p, &cos_p);
    const glm::vec3 wo_p(cos_p * cos_phi_o, sin_p, cos_p * sin_phi_o);
    const float mn = hair_longitudinal(wo_p, wi, v_[p]) * kTwoPi *
                     azimuthal(delta_phi, p, s_, gamma_o, gamma_t);
    f += mn * a_p[p];
    if (pdf) density += mn * a_pdf[p];
  }
  const float m_rest = hair_longitudinal(wo, wi, v_[kPMax]);
  f += m_rest * a_p[kPMax];
  if (pdf) density += m_rest * a_pdf[kPMax];
  if (value) *value = std::isfinite(f.x + f.y + f.z) ? f : glm::vec3(0.0f);
  if (pdf) *pdf = std::isfinite(density) ? density : 0.0f;
}

glm::vec3 HairBsdf::eval(glm::vec3 wo, glm::vec3 wi) const {
  glm::vec3 f;
  eval_pdf(wo, wi, &f, nullptr);
  return f;
}

float HairBsdf::pdf(glm::vec3 wo, glm::vec3 wi) const {
  float density = 0;
  eval_pdf(wo, wi, nullptr, &density);
  return density;
}

std::optional<BsdfSample> HairBsdf::sample(glm::vec3 wo, float u_lobe, glm::vec2 u) const {
  const float gamma_o = gamma_of(wo), h = std::sin(gamma_o);
  const float sin_theta_o = wo.y, cos_theta_o = safe_sqrt(1 - sin_theta_o * sin_theta_o);
  const float phi_o = std::atan2(wo.z, wo.x);
  float a_pdf[kPMax + 1];
  attenuation_pdf(wo, a_pdf);
  // Choose p by u_lobe, then rescale what is left of it to [0, 1) for the azimuth.
  float u0 = u_lobe, u1 = u_lobe / a_pdf[0];
  int p = 0;
  for (int i = 0; i < kPMax; ++i) {
    const bool next = a_pdf[i] < u0;
    u0 -= a_pdf[i];
    if (next) {
      p = i + 1;
      u1 = u0 / a_pdf[i + 1];
    }
  }
  u1 = std::clamp(u1, 0.0f, 1.0f);
  float sin_p = 0, cos_p = 0;
  reframe(sin_theta_o, cos_theta_o, p, &sin_p, &cos_p);
  // The longitudinal angle (d'Eon's sampling; exp(-2 / v) underflows for small roughness).
  float cos_theta = 1 + v_[p] * std::log(u.x + (1 - u.x) * std::exp(-2.0f / v_[p]));
  cos_theta = std::clamp(cos_theta, -1.0f, 1.0f);
  const float sin_theta = safe_sqrt(1 - cos_theta * cos_theta);
  const float cos_phi = std::cos(kTwoPi * u.y);
  const float sin_theta_i = -cos_theta * sin_p + sin_theta * cos_phi * cos_p;
  const float cos_theta_i = safe_sqrt(1 - sin_theta_i * sin_theta_i);
  const float eta_p = safe_sqrt(eta_ * eta_ - sin_theta_o * sin_theta_o) / cos_theta_o;
  const float gamma_t = safe_asin(h / eta_p);
  const float delta_phi = p < kPMax ? 2 * float(p) * gamma_t - 2 * gamma_o + float(p) * kPi +
                                          trimmed_logistic_sample(u1, s_)
                                    : kTwoPi * u1;
  const float phi_i = phi_o + delta_phi;
  const glm::vec3 wi = glm::normalize(glm::vec3(cos_theta_i * std::cos(phi_i), sin_theta_i,
                                                cos_theta_i * std::sin(phi_i)));
  BsdfSample s;
  s.wi = wi;
  glm::vec3 f;
  eval_pdf(wo, wi, &f, &s.pdf);
  if (!(s.pdf > 0)) return std::nullopt;
  s.weight = f / s.pdf;
  s.eta = 1;  // the walk crosses the fibre completely
  return s;
}

}  // namespace tessera
