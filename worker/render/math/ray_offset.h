// Spawning rays off surfaces without self-intersection, by floating-point error bounds
// (pbrt-v4's OffsetRayOrigin; Pharr, Jakob, Humphreys, "Physically Based Rendering", 4th ed.,
// section 6.8). There is no global epsilon: the offset is as large as the error of the
// computed hit point, which scales with the point's magnitude, so scenes of any scale work.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace tessera {

/// gamma(n) = n u / (1 - n u), the bound on the relative error of n chained float operations.
constexpr float gamma_bound(int n) {
  constexpr float u = std::numeric_limits<float>::epsilon() * 0.5f;
  return (float(n) * u) / (1.0f - float(n) * u);
}

/// The error box of a point interpolated on triangle (p0, p1, p2). pbrt bounds the error of
/// b0 p0 + b1 p1 + b2 p2 per axis; Embree, though, finds hits with its own float arithmetic
/// on vertex coordinates relative to the ray origin, so a ray leaving the triangle can be
/// reported to hit it again at an error as large as a few ulps of the largest coordinate
/// involved, along any axis (an axis-aligned floor at y = 0 has no error in y by pbrt's bound
/// yet is hit again). The bound is therefore that ulp-scaled magnitude on every axis.
inline float triangle_point_error(glm::vec3 p0, glm::vec3 p1, glm::vec3 p2);

/// The next float above v (pbrt-v4's NextFloatUp), without libm's errno handling.
inline float next_float_up(float v) {
  if (std::isinf(v) && v > 0.f) return v;
  if (v == -0.f) v = 0.f;
  uint32_t bits = std::bit_cast<uint32_t>(v);
  bits = v >= 0 ? bits + 1 : bits - 1;
  return std::bit_cast<float>(bits);
}

/// The next float below v.
inline float next_float_down(float v) {
  if (std::isinf(v) && v < 0.f) return v;
  if (v == 0.f) v = -0.f;
  uint32_t bits = std::bit_cast<uint32_t>(v);
  bits = v > 0 ? bits - 1 : bits + 1;
  return std::bit_cast<float>(bits);
}

/// A surface point with a conservative absolute error bound per coordinate.
struct SurfacePoint {
  glm::vec3 p;        ///< computed point
  glm::vec3 p_error;  ///< |computed - exact| <= p_error, per coordinate
  glm::vec3 ng;       ///< unit geometric normal (either orientation)
};

/// next_float_up(v) when offset > 0, next_float_down(v) when offset < 0, else v (a NaN offset
/// included): the same bits as those two, without their branches (the ray origin's hot path).
[[gnu::always_inline]] inline float next_float_away(float v, float offset) {
  // On the bits, so that the compiler needs no branch: |x| in [1, 0x7f800000] is a nonzero
  // number (not NaN), and a value counts as positive when v > 0 would be true.
  const uint32_t vb = std::bit_cast<uint32_t>(v), ob = std::bit_cast<uint32_t>(offset);
  const uint32_t va = vb & 0x7fffffffu, oa = ob & 0x7fffffffu;
  const bool up = (ob >> 31) == 0;
  const bool directed = oa - 1u < 0x7f800000u;  // offset > 0 or offset < 0
  const bool positive = vb - 1u < 0x7f800000u;  // v > 0
  const bool zero = va == 0;
  // Only +inf going up and -inf going down stay where they are.
  const bool moves = directed && !(va == 0x7f800000u && positive == up);
  // A zero of either sign steps to the smallest subnormal on the side it moves to.
  const uint32_t from = zero ? (up ? 0u : 0x80000000u) : vb;
  const uint32_t to = from + ((zero || positive == up) ? 1u : ~0u);
  return std::bit_cast<float>(moves ? to : vb);
}

/// The origin for a ray leaving `sp` in direction w: p pushed along the geometric normal, to
/// the side w points to, past the error box, then rounded one more ulp away.
[[gnu::always_inline]] inline glm::vec3 offset_ray_origin(const SurfacePoint& sp, glm::vec3 w) {
  const float d = glm::dot(glm::abs(sp.ng), sp.p_error);
  glm::vec3 offset = d * sp.ng;
  if (glm::dot(w, sp.ng) < 0) offset = -offset;
  const glm::vec3 po = sp.p + offset;
  return {next_float_away(po.x, offset.x), next_float_away(po.y, offset.y),
          next_float_away(po.z, offset.z)};
}

inline float max_abs_coordinate(glm::vec3 p0, glm::vec3 p1, glm::vec3 p2) {
  const glm::vec3 m = glm::max(glm::max(glm::abs(p0), glm::abs(p1)), glm::abs(p2));
  return std::max(m.x, std::max(m.y, m.z));
}

inline float triangle_point_error(glm::vec3 p0, glm::vec3 p1, glm::vec3 p2) {
  // A point on the triangle is a convex combination of the vertices, so no larger than they are.
  return gamma_bound(7) * max_abs_coordinate(p0, p1, p2);
}

}  // namespace tessera
