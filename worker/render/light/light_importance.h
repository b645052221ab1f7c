// Every light's importance at a shading point at once: LightBounds::importance in float, four
// lights per vector operation, from per-light constants computed once at scene build.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <vector>

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

}  // namespace tessera
