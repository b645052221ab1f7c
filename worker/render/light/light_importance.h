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

#include "render/light/light_bounds.h"
#include "render/math/float4.h"

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

  /// Light i's constants in every lane of V (M: its int32 mask type), for
  /// light_importance_detail::importance_lanes at kWidth<V> points at once: lane l then holds
  /// bit for bit evaluate_all's importance[i] at lane l's point (the wavefront kernels,
  /// wavefront_kernel.inc).
  template <class V, class M>
  [[gnu::always_inline]] auto light_lanes(uint32_t i) const;

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


// importance_lanes passes K-lane vectors between inlined functions only (float4.h): GCC's note
// that their ABI would differ without AVX does not apply.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

namespace light_importance_detail {

using namespace float4;  // Float4, Mask4 and their helpers (render/math/float4.h)

/// One light's constants in every lane of V (the same light at K points: the wavefront
/// kernels), or four lights' constants, one per lane of Float4 (one point: evaluate_all).
template <class V, class M>
struct LightLanes {
  V cx, cy, cz, radius, radius2, phi, inside, wx, wy, wz, cos_o, sin_o, cos_e, min_importance;
  M two_sided;
};

/// The importance of each lane's light at each lane's point p (normal n, where has_n: n != 0).
/// Written once and called for both layouts (four lights at one point, or one light at K
/// points), so a light's importance at a point has the same bits whichever computed it.
template <class V, class M>
[[gnu::always_inline]] inline V importance_lanes(const LightLanes<V, M>& b, V px, V py, V pz, V nx, V ny, V nz,
                                                 M has_n) {
  const V zero = splat_lanes<V>(0.0f), one = splat_lanes<V>(1.0f);
  const V dx = px - b.cx, dy = py - b.cy, dz = pz - b.cz;
  const V d2 = dx * dx + dy * dy + dz * dz;
  const V r2 = b.radius2;
  const V inv_dist = one / sqrt_lanes(d2);
  // theta_b: the half-angle the bounding sphere subtends at p.
  const V sin_b = b.radius * inv_dist;
  const V cos_b = sqrt_lanes(at_least(d2 - r2, zero)) * inv_dist;

  // At the light: theta_x = max(0, theta_w - theta_o), the smallest angle between a normal and
  // the direction to p's centre, then minus theta_b, compared with theta_e.
  V cos_w = (b.wx * dx + b.wy * dy + b.wz * dz) * inv_dist;
  cos_w = b.two_sided ? abs_lanes<V, M>(cos_w) : cos_w;
  const V cos_o = b.cos_o, sin_o = b.sin_o;
  const V sin_w = sqrt_lanes(at_least(one - cos_w * cos_w, zero));
  const M outside_cone = cos_w < cos_o;
  const V cos_x = outside_cone ? cos_w * cos_o + sin_w * sin_o : one;
  const V sin_x = outside_cone ? sin_w * cos_o - cos_w * sin_o : zero;
  const V cos_light = cos_x >= cos_b ? one : cos_x * cos_b + sin_x * sin_b;
  V importance = b.phi * cos_light / d2;

  // At p: the smallest angle between its normal (either side) and a direction to the light.
  const V cos_i = abs_lanes<V, M>((nx * dx + ny * dy + nz * dz) * inv_dist);
  const V sin_i = sqrt_lanes(at_least(one - cos_i * cos_i, zero));
  const V cos_p = cos_i >= cos_b ? one : cos_i * cos_b + sin_i * sin_b;
  importance = has_n ? importance * at_least(cos_p, splat_lanes<V>(1e-3f)) : importance;
  importance = at_most(at_least(importance, b.min_importance), splat_lanes<V>(LightImportance::kMaxImportance));
  // Unreachable only where the bound says so by more than float rounding (cos_e holds
  // cos theta_e - kReachSlack); a NaN (from an infinite distance) reaches.
  const M unreachable = cos_light <= b.cos_e;
  importance = unreachable ? zero : importance;
  // Inside the bounds there is no angle to bound (lights at infinity: always inside).
  return d2 <= r2 ? b.inside : importance;
}

/// The importance of the block's four lights at p (normal n, has_n: n != 0).
[[gnu::always_inline]] inline Float4 block_importance(const LightImportance::Block& b, Float4 px,
                                                      Float4 py, Float4 pz, Float4 nx, Float4 ny,
                                                      Float4 nz, bool has_n) {
  const LightLanes<Float4, Mask4> lanes{load(b.cx),     load(b.cy),    load(b.cz),    load(b.radius),
                                        load(b.radius2), load(b.phi),  load(b.inside), load(b.wx),
                                        load(b.wy),     load(b.wz),    load(b.cos_o), load(b.sin_o),
                                        load(b.cos_e),  load(b.min_importance), load(b.two_sided)};
  const int32_t n_mask = has_n ? -1 : 0;
  return importance_lanes<Float4, Mask4>(lanes, px, py, pz, nx, ny, nz, Mask4{n_mask, n_mask, n_mask, n_mask});
}

}  // namespace light_importance_detail

#pragma GCC diagnostic pop

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

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
template <class V, class M>
[[gnu::always_inline]] inline auto LightImportance::light_lanes(uint32_t i) const {
  const Block& b = blocks_[i / kLanes];
  const size_t k = i % kLanes;
  using float4::splat_lanes;
  M two_sided;
  for (int l = 0; l < float4::kWidth<V>; ++l) two_sided[l] = b.two_sided[k];
  return light_importance_detail::LightLanes<V, M>{
      splat_lanes<V>(b.cx[k]),     splat_lanes<V>(b.cy[k]),     splat_lanes<V>(b.cz[k]),
      splat_lanes<V>(b.radius[k]), splat_lanes<V>(b.radius2[k]), splat_lanes<V>(b.phi[k]),
      splat_lanes<V>(b.inside[k]), splat_lanes<V>(b.wx[k]),     splat_lanes<V>(b.wy[k]),
      splat_lanes<V>(b.wz[k]),     splat_lanes<V>(b.cos_o[k]),  splat_lanes<V>(b.sin_o[k]),
      splat_lanes<V>(b.cos_e[k]),  splat_lanes<V>(b.min_importance[k]), two_sided};
}

#pragma GCC diagnostic pop

}  // namespace tessera
