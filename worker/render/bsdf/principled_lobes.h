// The pieces of Mitsuba 3's principled BSDF that no other BSDF uses (Mitsuba's
// src/bsdfs/principledhelpers.h, after Burley's "Physically Based Shading at Disney", 2012):
// the GTR1 distribution of the clear coat, its GGX shadowing, Schlick's Fresnel approximation
// in Mitsuba's form, and the blend of dielectric and metallic Fresnel terms. Directions are in
// the local shading frame (+z = the front), as everywhere in worker/render/bsdf/.
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "render/sampling/warp.h"

namespace tessera::principled {

/// Linear-RGB luminance with Mitsuba's (sRGB / Rec. 709) weights.
inline float luminance(glm::vec3 c) { return 0.212671f * c.x + 0.715160f * c.y + 0.072169f * c.z; }

/// a + (b - a) t, as Mitsuba's lerp.
template <typename T>
T lerp(T a, T b, float t) {
  return a * (1.0f - t) + b * t;
}

/// Mitsuba's calc_dist_params: GGX alphas (u, v) from roughness and anisotropic, each at
/// least 0.001.
inline glm::vec2 specular_alphas(float roughness, float anisotropic) {
  const float r2 = roughness * roughness;
  const float aspect = std::sqrt(1.0f - 0.9f * anisotropic);
  return {std::max(0.001f, r2 / aspect), std::max(0.001f, r2 * aspect)};
}

/// The tint of Burley's tinted lobes: base_color over its luminance (white when black).
inline glm::vec3 tint_color(glm::vec3 base_color) {
  const float lum = luminance(base_color);
  return lum > 0.0f ? base_color / lum : glm::vec3(1.0f);
}

/// Burley's GTR1 ("generalised Trowbridge-Reitz", exponent 1) distribution of microfacet
/// normals of the clear coat; isotropic, alpha in (0, 1). No visible-normal sampling, as Mitsuba.
class Gtr1 {
 public:
  explicit Gtr1(float alpha) : alpha2_(alpha * alpha) {}
  /// D(m); its integral times cos(m) over the hemisphere is 1. 0 below the surface.
  float eval(glm::vec3 m) const {
    const float cos2 = m.z * m.z;
    const float d = (alpha2_ - 1.0f) / (kPi * std::log(alpha2_) * (1.0f + (alpha2_ - 1.0f) * cos2));
    return d * m.z > 1e-20f ? d : 0.0f;
  }
  /// The density of sample() over normals (solid angle): D(m) cos(m).
  float pdf(glm::vec3 m) const { return m.z < 0.0f ? 0.0f : m.z * eval(m); }
  /// A normal distributed as D(m) cos(m); u.x chooses the azimuth, u.y the elevation.
  glm::vec3 sample(glm::vec2 u) const {
    const float phi = 2.0f * kPi * u.x;
    const float cos2 = (1.0f - std::pow(alpha2_, 1.0f - u.y)) / (1.0f - alpha2_);
    const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos2));
    const float cos_theta = std::sqrt(std::max(0.0f, cos2));
    return {std::cos(phi) * sin_theta, std::sin(phi) * sin_theta, cos_theta};
  }

 private:
  float alpha2_;
};

/// Smith's GGX shadowing of direction v by facets of normal m for isotropic alpha (Mitsuba's
/// smith_ggx1, used by the clear coat with alpha 0.25); 0 when v sees the back of m.
inline float smith_ggx1(glm::vec3 v, glm::vec3 m, float alpha) {
  if (glm::dot(v, m) * v.z <= 0.0f) return 0.0f;
  if (v.z == 1.0f) return 1.0f;
  const float cos2 = v.z * v.z, tan2 = (1.0f - cos2) / cos2;
  return 2.0f / (1.0f + std::sqrt(1.0f + alpha * alpha * tan2));
}

/// (1 - cos)^5 with cos clamped to [0, 1].
inline float schlick_weight(float cos_i) {
  const float m = std::clamp(1.0f - cos_i, 0.0f, 1.0f);
  return (m * m) * (m * m) * m;
}

/// Schlick's reflectance R0 + (1 - R0) (1 - cos)^5 for a boundary of interior / exterior index
/// eta, cos_theta_i signed as in fresnel_dielectric_signed. Where the light arrives from the
/// denser side the refracted angle's cosine is used (0 under total internal reflection).
template <typename T>
T schlick(T r0, float cos_theta_i, float eta) {
  const bool outside = cos_theta_i >= 0.0f;
  const float eta_it = outside ? eta : 1.0f / eta, eta_ti = outside ? 1.0f / eta : eta;
  const float cos_t2 = 1.0f - (1.0f - cos_theta_i * cos_theta_i) * (eta_ti * eta_ti);
  const float cos_t = std::sqrt(std::max(0.0f, cos_t2));
  const float w = eta_it > 1.0f ? schlick_weight(std::abs(cos_theta_i)) : schlick_weight(cos_t);
  return T(w) * (T(1.0f) - r0) + r0;  // Mitsuba's lerp(w, 1, r0)
}

/// Normal-incidence reflectance ((eta - 1) / (eta + 1))^2.
inline float schlick_r0(float eta) {
  const float r = (eta - 1.0f) / (eta + 1.0f);
  return r * r;
}

/// Mitsuba's mac_mic_compatibility: wo and wi lie on the sides of the microfacet m (oriented
/// to wo's side of the macro surface) that a reflection (both on wo's side) or a refraction
/// (wi on the other) needs.
inline bool facet_compatible(glm::vec3 m, glm::vec3 wo, glm::vec3 wi, float cos_theta_o,
                             bool reflection) {
  const glm::vec3 mo = std::signbit(cos_theta_o) ? -m : m;
  const float dot_i = glm::dot(wi, mo);
  return glm::dot(wo, mo) > 0.0f && (reflection ? dot_i > 0.0f : dot_i < 0.0f);
}

}  // namespace tessera::principled
