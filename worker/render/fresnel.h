// Smooth-dielectric optics: Fresnel reflectance, mirror reflection, Snell refraction.
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

}  // namespace tessera
