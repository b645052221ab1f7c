// Every light's importance at a shading point at once: LightBounds::importance in float, four
// lights per vector operation, from per-light constants computed once at scene build.
#pragma once

#include <array>
#include <cmath>
#include <cstring>
#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <vector>

#include "render/float4.h"
#include "render/light/light_bounds.h"

namespace tessera {

/// LightBounds::importance for up to kMaxLights lights, evaluated together: the same bounds of
/// the cosines at the light and at the point, compared as cosines (pbrt-v4), in float, with no
/// transcendental function (square roots and divisions only). Lane-wise IEEE operations with no
/// fused multiply-add, so a light's importance has the same bits on every instruction set and
/// whether it is evaluated alone (evaluate) or with the others (evaluate_all).
///
/// Where they differ from LightBounds::importance (besides float rounding, which
/// light_importance_test bounds):
/// - powers are divided by the largest one, and every light that may reach the point counts
///   with an importance in [kMinImportance, kMaxImportance] (clamped), so no float underflow or
///   overflow can take a reachable light's probability to 0 or make a sum infinite;
/// - a light counts as unreachable only where the bound of the cosine at the light lies below
///   cos theta_e by more than kReachSlack (float rounding cannot exclude a light that reaches);
///   a NaN (a point at an infinite distance) counts as reachable, never as 0.
/// A light with power 0 has importance 0 everywhere.
class LightImportance {
 public:
  static constexpr size_t kLanes = 4;
  static constexpr size_t kMaxLights = 16;
  static constexpr float kMinImportance = 1e-15f;
  static constexpr float kMaxImportance = 1e15f;
  static constexpr float kReachSlack = 1e-5f;

  LightImportance() = default;
  /// At most kMaxLights bounds (std::invalid_argument otherwise), each with finite phi >= 0.
  explicit LightImportance(const std::vector<LightBounds>& bounds);

  size_t size() const { return count_; }

  /// Writes every light's importance at p (unit geometric normal n, either side; n == 0: a point
  /// in a medium) into importance[0 .. size()) and returns their sum, added in light order
  /// (0 when no light can reach p). `importance` must hold kMaxLights floats.
  /// Inline (below: the light picker's hot path, built into each wavefront kernel's
  /// instruction set); more than one block goes out of line.
  float evaluate_all(const glm::vec3& p, const glm::vec3& n, float* importance) const;
  /// Light i's importance at p: bit for bit evaluate_all's importance[i].
  float evaluate(uint32_t i, const glm::vec3& p, const glm::vec3& n) const;

  /// The constants of kLanes lights, one array per quantity (padding lanes never reach).
  struct Block {
    alignas(16) float cx[kLanes], cy[kLanes], cz[kLanes];  ///< bounding sphere centre
    alignas(16) float radius[kLanes], radius2[kLanes];
    alignas(16) float phi[kLanes];          ///< power / the largest power
    alignas(16) float inside[kLanes];       ///< the importance within the bounding sphere
    alignas(16) float wx[kLanes], wy[kLanes], wz[kLanes];  ///< normal cone axis
    alignas(16) float cos_o[kLanes], sin_o[kLanes];       ///< normal cone half-angle
    alignas(16) float cos_e[kLanes];  ///< cos of the emission half-angle, - kReachSlack
    alignas(16) float min_importance[kLanes];  ///< kMinImportance, 0 for a light of power 0
    alignas(16) int32_t two_sided[kLanes];     ///< -1: |cos| at the light, 0: one-sided
  };

 private:
  /// evaluate_all for any number of blocks (kept out of line: its loop would otherwise make
  /// the one-block case keep its inputs on the stack).
  [[gnu::noinline]] float evaluate_blocks(const glm::vec3& p, const glm::vec3& n, bool has_n,
                                          float* importance) const;

  std::array<Block, kMaxLights / kLanes> blocks_{};
  uint32_t block_count_ = 0;
  uint32_t count_ = 0;
};


namespace light_importance_detail {

using namespace float4;  // Float4, Mask4 and their helpers (render/float4.h)

/// The importance of the block's four lights at p (normal n, has_n: n != 0). Written once,
/// called by evaluate_all and evaluate alike, so a lane's bits never depend on the caller.
[[gnu::always_inline]] inline Float4 block_importance(const LightImportance::Block& b, Float4 px,
                                                      Float4 py, Float4 pz, Float4 nx, Float4 ny,
                                                      Float4 nz, bool has_n) {
  const Float4 zero = splat(0.0f), one = splat(1.0f);
  const Float4 dx = px - load(b.cx), dy = py - load(b.cy), dz = pz - load(b.cz);
  const Float4 d2 = dx * dx + dy * dy + dz * dz;
  const Float4 r2 = load(b.radius2);
  const Float4 inv_dist = one / sqrt4(d2);
  // theta_b: the half-angle the bounding sphere subtends at p.
  const Float4 sin_b = load(b.radius) * inv_dist;
  const Float4 cos_b = sqrt4(at_least(d2 - r2, zero)) * inv_dist;

  // At the light: theta_x = max(0, theta_w - theta_o), the smallest angle between a normal and
  // the direction to p's centre, then minus theta_b, compared with theta_e.
  Float4 cos_w = (load(b.wx) * dx + load(b.wy) * dy + load(b.wz) * dz) * inv_dist;
  cos_w = load(b.two_sided) ? abs4(cos_w) : cos_w;
  const Float4 cos_o = load(b.cos_o), sin_o = load(b.sin_o);
  const Float4 sin_w = sqrt4(at_least(one - cos_w * cos_w, zero));
  const Mask4 outside_cone = cos_w < cos_o;
  const Float4 cos_x = outside_cone ? cos_w * cos_o + sin_w * sin_o : one;
  const Float4 sin_x = outside_cone ? sin_w * cos_o - cos_w * sin_o : zero;
  const Float4 cos_light = cos_x >= cos_b ? one : cos_x * cos_b + sin_x * sin_b;
  Float4 importance = load(b.phi) * cos_light / d2;

  // At p: the smallest angle between its normal (either side) and a direction to the light.
  if (has_n) {
    const Float4 cos_i = abs4((nx * dx + ny * dy + nz * dz) * inv_dist);
    const Float4 sin_i = sqrt4(at_least(one - cos_i * cos_i, zero));
    const Float4 cos_p = cos_i >= cos_b ? one : cos_i * cos_b + sin_i * sin_b;
    importance *= at_least(cos_p, splat(1e-3f));
  }
  importance = at_most(at_least(importance, load(b.min_importance)),
                       splat(LightImportance::kMaxImportance));
  // Unreachable only where the bound says so by more than float rounding (cos_e holds
  // cos theta_e - kReachSlack); a NaN (from an infinite distance) reaches.
  const Mask4 unreachable = cos_light <= load(b.cos_e);
  importance = unreachable ? zero : importance;
  // Inside the bounds there is no angle to bound (lights at infinity: always inside).
  return d2 <= r2 ? load(b.inside) : importance;
}

}  // namespace light_importance_detail

[[gnu::always_inline]] inline float LightImportance::evaluate_all(const glm::vec3& p, const glm::vec3& n,
                                                                  float* importance) const {
  using namespace light_importance_detail;
  const bool has_n = n.x != 0 || n.y != 0 || n.z != 0;  // else a point in a medium
  if (block_count_ != 1) return evaluate_blocks(p, n, has_n, importance);
  // Up to four lights (the benchmark scenes): one block, no loop, nothing kept on the stack.
  const Float4 v = block_importance(blocks_[0], splat(p.x), splat(p.y), splat(p.z), splat(n.x),
                                    splat(n.y), splat(n.z), has_n);
  std::memcpy(importance, &v, sizeof v);
  float sum = 0;
  for (uint32_t i = 0; i < count_; ++i) sum += v[i];
  return sum;
}

}  // namespace tessera
