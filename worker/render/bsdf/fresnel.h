// Fresnel equations, mirror reflection and refraction, in the conventions of Mitsuba 3
// (include/mitsuba/render/fresnel.h): directions point away from the surface, eta is the
// interior index over the exterior one, and the local frame's +z is the exterior side.
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace tessera {

/// Unpolarised Fresnel reflectance of a smooth boundary between dielectrics.
/// cos_i: cosine between the incident direction and the normal on the incident side, in [0, 1].
/// eta: relative index eta_t / eta_i (transmitted side over incident side), > 0.
/// Returns R in [0, 1]; R = 1 under total internal reflection. *cos_t receives the cosine of
/// the refracted direction (0 under total internal reflection).
inline float fresnel_dielectric(float cos_i, float eta, float* cos_t) {
  cos_i = std::clamp(cos_i, 0.0f, 1.0f);
  const float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.0f) {
    *cos_t = 0.0f;
    return 1.0f;
  }
  const float ct = std::sqrt(1.0f - sin2_t);
  *cos_t = ct;
  const float r_s = (cos_i - eta * ct) / (cos_i + eta * ct);
  const float r_p = (eta * cos_i - ct) / (eta * cos_i + ct);
  return std::clamp(0.5f * (r_s * r_s + r_p * r_p), 0.0f, 1.0f);
}

/// Mirror reflection of wo (pointing away from the surface) about the unit normal n.
inline glm::vec3 reflect(glm::vec3 wo, glm::vec3 n) { return 2.0f * glm::dot(wo, n) * n - wo; }

/// Snell refraction of wo (pointing away from the surface, on n's side) through a boundary of
/// relative index eta = eta_t / eta_i; cos_t from fresnel_dielectric. Returns the unit
/// transmitted direction, on the side opposite n.
inline glm::vec3 refract(glm::vec3 wo, glm::vec3 n, float eta, float cos_t) {
  const float cos_i = glm::dot(wo, n);
  return glm::normalize(-wo / eta + (cos_i / eta - cos_t) * n);
}

/// The dielectric Fresnel term for a direction on either side of the boundary.
struct DielectricFresnel {
  float r = 1;            ///< reflectance in [0, 1]; 1 under total internal reflection
  /// Signed cosine of the refracted direction (on the side opposite wi); 0 under TIR.
  float cos_theta_t = 0;
  float eta_it = 1;       ///< index on the transmitted side over the incident side's
  float eta_ti = 1;       ///< its inverse
};

/// Mitsuba's fresnel(cos_theta_i, eta): cos_theta_i is the signed cosine between the incident
/// direction and the normal (negative = arriving from the interior); eta = interior / exterior
/// index, > 0. eta == 1 reflects nothing; cos_theta_i == 0 reflects everything.
inline DielectricFresnel fresnel_dielectric_signed(float cos_theta_i, float eta) {
  const bool outside = cos_theta_i >= 0.0f;
  DielectricFresnel f;
  f.eta_it = outside ? eta : 1.0f / eta;
  f.eta_ti = outside ? 1.0f / eta : eta;
  const float cos_t2 = 1.0f - (1.0f - cos_theta_i * cos_theta_i) * (f.eta_ti * f.eta_ti);
  const float cos_i = std::abs(cos_theta_i);
  const float cos_t = std::sqrt(std::max(0.0f, cos_t2));
  if (eta == 1.0f || cos_i == 0.0f) {
    f.r = eta == 1.0f ? 0.0f : 1.0f;
  } else {
    const float a_s = (cos_i - f.eta_it * cos_t) / (cos_i + f.eta_it * cos_t);
    const float a_p = (cos_t - f.eta_it * cos_i) / (cos_t + f.eta_it * cos_i);
    f.r = std::clamp(0.5f * (a_s * a_s + a_p * a_p), 0.0f, 1.0f);
  }
  f.cos_theta_t = outside ? -cos_t : cos_t;
  return f;
}

/// Fresnel reflectance of a conductor with complex index eta + i k relative to the exterior,
/// per RGB channel, for the unsigned cosine cos_theta_i in [0, 1] (Mitsuba's fresnel_conductor,
/// the exact unpolarised formula). k = 0 gives the dielectric result for eta >= 1.
inline glm::vec3 fresnel_conductor(float cos_theta_i, glm::vec3 eta, glm::vec3 k) {
  const float c2 = cos_theta_i * cos_theta_i, s2 = 1.0f - c2, s4 = s2 * s2;
  glm::vec3 r;
  for (int c = 0; c < 3; ++c) {
    const float temp = eta[c] * eta[c] - k[c] * k[c] - s2;
    const float ek = eta[c] * k[c];
    const float a2pb2 = std::sqrt(std::max(0.0f, temp * temp + 4.0f * ek * ek));
    const float a = std::sqrt(std::max(0.0f, 0.5f * (a2pb2 + temp)));
    const float t1 = a2pb2 + c2, t2 = 2.0f * cos_theta_i * a;
    const float r_s = t1 + t2 > 0.0f ? (t1 - t2) / (t1 + t2) : 1.0f;
    const float t3 = a2pb2 * c2 + s4, t4 = t2 * s2;
    const float r_p = t3 + t4 > 0.0f ? r_s * (t3 - t4) / (t3 + t4) : r_s;
    r[c] = std::clamp(0.5f * (r_s + r_p), 0.0f, 1.0f);
  }
  return r;
}

/// Hemispherical average of the dielectric Fresnel reflectance for light arriving from a side
/// where the relative index is eta (Mitsuba's fresnel_diffuse_reflectance: d'Eon and Irving's
/// fit for eta < 1, Egan and Hilgeman's above).
inline float fresnel_diffuse_reflectance(float eta) {
  const float inv = 1.0f / eta;
  if (eta < 1.0f) return 0.0636f * inv + (eta * (eta * -1.4399f + 0.7099f) + 0.6681f);
  // Horner form of 0.919317 - 3.4793 x + 6.75335 x^2 - 7.80989 x^3 + 4.98554 x^4 - 1.36881 x^5.
  const float tail = -7.80989f + inv * (4.98554f + inv * -1.36881f);
  return 0.919317f + inv * (-3.4793f + inv * (6.75335f + inv * tail));
}

/// Reflection about the local +z axis.
inline glm::vec3 reflect_z(glm::vec3 wi) { return {-wi.x, -wi.y, wi.z}; }

/// Refraction of wi through a boundary with the local +z normal; cos_theta_t and eta_ti from
/// fresnel_dielectric_signed.
inline glm::vec3 refract_z(glm::vec3 wi, float cos_theta_t, float eta_ti) {
  return {-eta_ti * wi.x, -eta_ti * wi.y, cos_theta_t};
}

/// Refraction of wi through a microfacet of unit normal m (any side); cos_theta_t and eta_ti
/// from fresnel_dielectric_signed(dot(wi, m), eta).
inline glm::vec3 refract_m(glm::vec3 wi, glm::vec3 m, float cos_theta_t, float eta_ti) {
  return m * (glm::dot(wi, m) * eta_ti + cos_theta_t) - wi * eta_ti;
}

}  // namespace tessera
