// Warps from the unit square to the domains the renderer samples, with their densities.
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace tessera {

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 0.31830988618379067154f;
inline constexpr double kPiD = 3.14159265358979323846;

/// sin(x) and cos(x) for x in [-pi/4, pi/4], from Cephes' single-precision minimax polynomials
/// (sinf.c, cosf.c: within about 1 ulp of the exact values there). Ours rather than libm's
/// sinf/cosf so that every caller, scalar or lane-wise, and every kernel instruction set gets the
/// same bits from plain IEEE multiplies and adds (-ffp-contract=off: no fused multiply-add), and
/// so that the hot cosine-weighted direction needs no call into libm (docs/renderer.md, "Random
/// numbers"). A template so that the wavefront kernels' lane-wise copy (F a GCC vector of
/// floats: wavefront/wavefront_kernel.inc) runs this very expression, operation for operation.
template <typename F>
[[gnu::always_inline]] inline void sincos_quarter_pi(F x, F* sin_x, F* cos_x) {
  const F z = x * x;
  *sin_x = ((-1.9515295891e-4f * z + 8.3321608736e-3f) * z - 1.6666654611e-1f) * z * x + x;
  *cos_x = ((2.443315711809948e-5f * z - 1.388731625493765e-3f) * z + 4.166664568298827e-2f) * z * z -
           0.5f * z + 1.0f;
}

/// Shirley-Chiu concentric map of [0,1)^2 onto the unit disk (area preserving, low distortion).
/// The angle is pi/4 (o.y / o.x) in the sectors where |o.x| > |o.y|, else pi/2 - pi/4 (o.x / o.y),
/// whose cosine and sine are the sine and cosine of pi/4 (o.x / o.y): one sincos_quarter_pi either
/// way.
[[gnu::always_inline]] inline glm::vec2 square_to_concentric_disk(glm::vec2 u) {
  const glm::vec2 o = 2.0f * u - glm::vec2(1.0f);
  if (o.x == 0.0f && o.y == 0.0f) return {0.0f, 0.0f};
  float s, c;
  if (std::abs(o.x) > std::abs(o.y)) {
    sincos_quarter_pi((kPi / 4.0f) * (o.y / o.x), &s, &c);
    return {o.x * c, o.x * s};
  }
  sincos_quarter_pi((kPi / 4.0f) * (o.x / o.y), &s, &c);
  return {o.y * s, o.y * c};
}

/// Cosine-weighted direction on the hemisphere around +z (Malley's method): pdf = cos(theta)/pi.
[[gnu::always_inline]] inline glm::vec3 square_to_cosine_hemisphere(glm::vec2 u) {
  const glm::vec2 d = square_to_concentric_disk(u);
  const float z = std::sqrt(std::max(0.0f, 1.0f - d.x * d.x - d.y * d.y));
  return {d.x, d.y, z};
}

inline float cosine_hemisphere_pdf(float cos_theta) { return cos_theta > 0 ? cos_theta * kInvPi : 0; }

/// Barycentrics (b1, b2) of a uniformly distributed point on a triangle (Heitz 2019's
/// low-distortion map, which keeps the stratification of u).
inline glm::vec2 square_to_triangle(glm::vec2 u) {
  float b0, b1;
  if (u.y > u.x) {
    b0 = u.x / 2.0f;
    b1 = u.y - b0;
  } else {
    b1 = u.y / 2.0f;
    b0 = u.x - b1;
  }
  return {b0, b1};  // weights of v1 and v2; v0 gets 1 - b0 - b1
}

/// Uniform direction on the unit sphere: pdf = 1 / (4 pi).
inline glm::vec3 square_to_uniform_sphere(glm::vec2 u) {
  const float z = 1.0f - 2.0f * u.x;
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const float phi = 2.0f * kPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

}  // namespace tessera
