// Phase functions of participating media: isotropic and Henyey-Greenstein (Mitsuba's `hg`).
//
// Directions follow the path: `d` is the direction the ray travelled to the scattering point,
// `wi` the direction it leaves in. cos_theta = dot(d, wi), so g > 0 scatters forward (Mitsuba's
// hg, src/phase/hg.cpp, writes the same density with its wi = -d).
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "render/math/frame.h"
#include "render/sampling/warp.h"

namespace tessera {

/// The Henyey-Greenstein density over the sphere (1 / sr) of scattering by angle theta, for
/// mean cosine g in (-1, 1); g = 0 is isotropic, 1 / (4 pi).
inline float hg_density(float cos_theta, float g) {
  const float denom = 1.0f + g * g - 2.0f * g * cos_theta;
  return (0.25f * kInvPi) * (1.0f - g * g) / (denom * std::sqrt(denom));
}

/// cos theta drawn with density proportional to hg_density (u in [0, 1)): the inverse of its
/// CDF in cos theta, which is exact in closed form. Near g = 0 the closed form loses all its
/// digits (it divides by g), so |g| < 1e-3 samples the isotropic 1 - 2u instead, whose density
/// differs from HG's by under 0.3 % there and which hg_density then weighs exactly: phase
/// sampling reports hg_density as its pdf, so a path's weight stays f / pdf = 1 only up to that
/// factor, which the weight carries (PhaseSample::weight).
inline float hg_sample_cos(float u, float g) {
  if (std::abs(g) < 1e-3f) return std::clamp(1.0f - 2.0f * u, -1.0f, 1.0f);
  const float s = (1.0f - g * g) / (1.0f - g + 2.0f * g * u);
  return std::clamp((1.0f + g * g - s * s) / (2.0f * g), -1.0f, 1.0f);
}

struct PhaseSample {
  glm::vec3 wi;
  float pdf;     ///< solid-angle density of wi
  float weight;  ///< phase value / pdf: 1 but where |g| < 1e-3 (hg_sample_cos)
};

/// A phase function: `g` = 0 for isotropic.
class PhaseFunction {
 public:
  explicit PhaseFunction(float g = 0) : g_(g) {}
  float g() const { return g_; }

  /// The density of leaving along wi after arriving along d (both unit); the phase value and its
  /// sampling pdf are the same function.
  float eval(glm::vec3 d, glm::vec3 wi) const {
    if (g_ == 0) return 0.25f * kInvPi;
    return hg_density(glm::dot(d, wi), g_);
  }

  /// A direction around d (unit), u in [0, 1)^2.
  PhaseSample sample(glm::vec3 d, glm::vec2 u) const {
    const float cos_theta = g_ == 0 ? 1.0f - 2.0f * u.x : hg_sample_cos(u.x, g_);
    const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
    const float phi = 2.0f * kPi * u.y;
    const glm::vec3 local(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta);
    const glm::vec3 wi = glm::normalize(Frame(d).to_world(local));
    const float pdf = eval(d, wi);
    // Exact sampling: value / pdf = 1, except for the isotropic stand-in at tiny |g|.
    const float weight = (g_ == 0 || std::abs(g_) >= 1e-3f) ? 1.0f : pdf / (0.25f * kInvPi);
    return {wi, pdf, weight};
  }

 private:
  float g_;
};

}  // namespace tessera
