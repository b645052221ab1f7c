#include "render/bsdf/microfacet.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "render/sampling/warp.h"

namespace tessera {
namespace {

constexpr float kInvSqrtPi = 0.56418958354775628695f;

float sqr(float x) { return x * x; }
/// sqrt(max(0, x)): 0 for a negative x and for NaN (hair.cpp's safe_sqrt keeps NaN).
float sqrt_clamped(float x) { return std::sqrt(std::max(0.0f, x)); }

}  // namespace

float erfinv(float x) {
  // Giles' single-precision approximation; the standard library has no inverse erf.
  float w = -std::log(std::max((1.0f - x) * (1.0f + x), 1e-30f)), p;
  if (w < 5.0f) {
    w -= 2.5f;
    p = 2.81022636e-08f;
    p = 3.43273939e-07f + p * w;
    p = -3.5233877e-06f + p * w;
    p = -4.39150654e-06f + p * w;
    p = 0.00021858087f + p * w;
    p = -0.00125372503f + p * w;
    p = -0.00417768164f + p * w;
    p = 0.246640727f + p * w;
    p = 1.50140941f + p * w;
  } else {
    w = std::sqrt(w) - 3.0f;
    p = -0.000200214257f;
    p = 0.000100950558f + p * w;
    p = 0.00134934322f + p * w;
    p = -0.00367342844f + p * w;
    p = 0.00573950773f + p * w;
    p = -0.0076224613f + p * w;
    p = 0.00943887047f + p * w;
    p = 1.00167406f + p * w;
    p = 2.83297682f + p * w;
  }
  return p * x;
}

Microfacet::Microfacet(MicrofacetDistribution type, float alpha_u, float alpha_v,
                       bool sample_visible)
    : type_(type),
      alpha_u_(std::max(alpha_u, kMinAlpha)),
      alpha_v_(std::max(alpha_v, kMinAlpha)),
      sample_visible_(sample_visible) {}

void Microfacet::scale_alpha(float s) {
  alpha_u_ *= s;
  alpha_v_ *= s;
}

float Microfacet::eval(glm::vec3 m) const {
  const float cos2 = m.z * m.z;
  if (m.z <= 0.0f || cos2 == 0.0f) return 0.0f;
  const float xu = m.x / alpha_u_, yv = m.y / alpha_v_;
  float d;
  if (type_ == MicrofacetDistribution::beckmann) {
    d = std::exp(-(xu * xu + yv * yv) / cos2) / (kPi * alpha_u_ * alpha_v_ * cos2 * cos2);
  } else {
    d = 1.0f / (kPi * alpha_u_ * alpha_v_ * sqr(xu * xu + yv * yv + cos2));
  }
  return d * m.z > 1e-20f && std::isfinite(d) ? d : 0.0f;
}

float Microfacet::pdf(glm::vec3 wi, glm::vec3 m) const {
  const float d = eval(m);
  if (!sample_visible_) return d * m.z;
  if (wi.z == 0.0f) return 0.0f;
  return d * smith_g1(wi, m) * std::abs(glm::dot(wi, m)) / wi.z;
}

float Microfacet::smith_g1(glm::vec3 v, glm::vec3 m) const {
  if (glm::dot(v, m) * v.z <= 0.0f) return 0.0f;
  const float xy2 = sqr(alpha_u_ * v.x) + sqr(alpha_v_ * v.y);
  if (xy2 == 0.0f) return 1.0f;
  const float tan2 = xy2 / sqr(v.z);
  if (type_ == MicrofacetDistribution::beckmann) {
    // Walter et al.'s rational approximation of the Beckmann shadowing, as Mitsuba uses it.
    const float a = 1.0f / std::sqrt(tan2);
    if (a >= 1.6f) return 1.0f;
    return (3.535f * a + 2.181f * a * a) / (1.0f + 2.276f * a + 2.577f * a * a);
  }
  return 2.0f / (1.0f + std::sqrt(1.0f + tan2));
}

std::pair<glm::vec3, float> Microfacet::sample(glm::vec3 wi, glm::vec2 u) const {
  if (!sample_visible_) {
    float sin_phi, cos_phi, alpha2;
    if (alpha_u_ == alpha_v_) {
      sin_phi = std::sin(2.0f * kPi * u.y);
      cos_phi = std::cos(2.0f * kPi * u.y);
      alpha2 = alpha_u_ * alpha_u_;
    } else {
      const float tmp = (alpha_v_ / alpha_u_) * std::tan(2.0f * kPi * u.y);
      cos_phi = std::copysign(1.0f / std::sqrt(tmp * tmp + 1.0f), std::abs(u.y - 0.5f) - 0.25f);
      sin_phi = cos_phi * tmp;
      alpha2 = 1.0f / (sqr(cos_phi / alpha_u_) + sqr(sin_phi / alpha_v_));
    }
    float cos_theta;
    if (type_ == MicrofacetDistribution::beckmann) {
      cos_theta = 1.0f / std::sqrt(1.0f - alpha2 * std::log(1.0f - u.x));
    } else {
      const float tan2 = alpha2 * u.x / (1.0f - u.x);
      cos_theta = 1.0f / std::sqrt(1.0f + tan2);
    }
    const float sin_theta = sqrt_clamped(1.0f - cos_theta * cos_theta);
    const glm::vec3 m(cos_phi * sin_theta, sin_phi * sin_theta, cos_theta);
    return {m, pdf(wi, m)};
  }
  // Stretch wi to the unit-roughness configuration, sample the slopes there, unstretch.
  const glm::vec3 wi_p = glm::normalize(glm::vec3(alpha_u_ * wi.x, alpha_v_ * wi.y, wi.z));
  const float sin_theta = sqrt_clamped(1.0f - wi_p.z * wi_p.z);
  float cos_phi = 1.0f, sin_phi = 0.0f;
  if (sin_theta > 0.0f) {
    cos_phi = std::clamp(wi_p.x / sin_theta, -1.0f, 1.0f);
    sin_phi = std::clamp(wi_p.y / sin_theta, -1.0f, 1.0f);
  }
  glm::vec2 slope = sample_visible_11(wi_p.z, u);
  slope = {(cos_phi * slope.x - sin_phi * slope.y) * alpha_u_,
           (sin_phi * slope.x + cos_phi * slope.y) * alpha_v_};
  const glm::vec3 m = glm::normalize(glm::vec3(-slope.x, -slope.y, 1.0f));
  return {m, pdf(wi, m)};
}

glm::vec2 Microfacet::sample_visible_11(float cos_theta_i, glm::vec2 u) const {
  if (type_ == MicrofacetDistribution::beckmann) {
    // Jakob's numerical inversion of the visible-slope CDF (Mitsuba's sample_visible_11).
    const float tan_theta_i = sqrt_clamped(1.0f - cos_theta_i * cos_theta_i) / cos_theta_i;
    const float cot_theta_i = 1.0f / tan_theta_i;
    const float maxval = std::erf(cot_theta_i);
    u = glm::clamp(u, glm::vec2(1e-6f), glm::vec2(1.0f - 1e-6f));
    float x = maxval - (maxval + 1.0f) * std::erf(std::sqrt(-std::log(u.x)));
    u.x *= 1.0f + maxval + kInvSqrtPi * tan_theta_i * std::exp(-cot_theta_i * cot_theta_i);
    for (int i = 0; i < 3; ++i) {
      const float slope = erfinv(x);
      const float value = 1.0f + x + kInvSqrtPi * tan_theta_i * std::exp(-slope * slope) - u.x;
      const float derivative = 1.0f - slope * tan_theta_i;
      x -= value / derivative;
    }
    return {erfinv(x), erfinv(2.0f * u.y - 1.0f)};
  }
  // GGX: the visible normals of the unit-roughness distribution project to a disk deformed
  // by the incident angle (Heitz's construction, as Mitsuba writes it).
  glm::vec2 p = square_to_concentric_disk(u);
  const float s = 0.5f * (1.0f + cos_theta_i);
  p.y = (1.0f - s) * sqrt_clamped(1.0f - p.x * p.x) + s * p.y;
  const float z = sqrt_clamped(1.0f - glm::dot(p, p));
  const float sin_theta_i = sqrt_clamped(1.0f - cos_theta_i * cos_theta_i);
  const float norm = 1.0f / (sin_theta_i * p.y + cos_theta_i * z);
  return glm::vec2(cos_theta_i * p.y - sin_theta_i * z, p.x) * norm;
}

}  // namespace tessera
