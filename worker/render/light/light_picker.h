// Choosing which light a shading point samples.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "render/light/light_bounds.h"
#include "render/light/light_importance.h"
#include "render/light/piecewise_constant.h"
#include "render/math/ray_offset.h"

namespace tessera {

/// Every light's importance at one shading point, worked out ahead by a caller that evaluates
/// many points at once (the wavefront kernels: LightImportance::light_lanes): light i's at
/// values[i * stride], and their sum, added in light order, in total; bit for bit what
/// LightImportance::evaluate_all gives at that point.
struct PointImportance {
  const float* values;
  uint32_t stride;
  float total;
};

/// Picks one light per shading point. With 2 to kMaxPerPoint lights, with probability
/// proportional to each light's importance at the point (LightImportance: LightBounds::importance
/// with the point's geometric normal, in float: power, distance and the cosine bounds at both
/// ends, no visibility), so that near lights facing the point are picked more often and lights
/// that cannot reach it (one-sided lights seen from behind) not at all. With more lights (where
/// evaluating every light at every point would cost more than it saves, and a light BVH is
/// future work) and with one, by power alone (pbrt's PowerLightSampler); when every power is 0,
/// uniformly.
class LightPicker {
 public:
  static constexpr size_t kMaxPerPoint = LightImportance::kMaxLights;
  /// An importance sum not known to the caller: pmf() computes it.
  static constexpr float kUnknownSum = -1.0f;

  /// One bounds and one power (finite, >= 0) per light, in the same order.
  LightPicker(std::vector<LightBounds> bounds, const std::vector<double>& powers);

  /// Index of the chosen light from u in [0, 1), its probability in `pmf` (> 0). When no
  /// light can reach ref (every importance 0), returns 0 with *pmf = 0. If `sum` is given, the
  /// sum of the importances at ref goes there (kUnknownSum when picking by power), for pmf()
  /// at the same ref. Must not be called without lights.
  /// `given`, when not null, holds the importances at ref (picking per point only; ignored
  /// otherwise), so that they are not evaluated again: the same light, pmf and sum.
  [[gnu::always_inline]] uint32_t pick(float u, const SurfacePoint& ref, float* pmf, float* sum = nullptr,
                                       const PointImportance* given = nullptr) const {
    // By power inline: a scene of one light pays nothing for picking per point, nor for
    // searching a distribution of one.
    if (!per_point()) {
      if (sum) *sum = kUnknownSum;
      if (single_) {
        *pmf = 1.0f;
        return 0;
      }
      return distribution_.sample_discrete(u, pmf);
    }
    if (given) return pick_among(u, given->values, given->stride, given->total, pmf, sum);
    return pick_per_point(u, ref, pmf, sum);
  }
  /// The probability pick() gives light i at ref (bit for bit the pmf pick() reports). `sum`:
  /// what pick() at this very ref reported, so that only light i's importance is evaluated, or
  /// kUnknownSum (any negative value): every light's, for their sum.
  float pmf(uint32_t i, const SurfacePoint& ref, float sum = kUnknownSum) const {
    if (!per_point()) return single_ ? 1.0f : distribution_.pmf(i);
    return pmf_per_point(i, ref, sum);
  }

  /// The sum pick() reports for ref (kUnknownSum when picking by power).
  float importance_sum(const SurfacePoint& ref) const;

  /// The lights' importance where pick() weighs them per point, else null.
  const LightImportance* point_importance() const { return per_point() ? &importance_ : nullptr; }

 private:
  uint32_t pick_per_point(float u, const SurfacePoint& ref, float* pmf, float* sum) const;
  /// pick_per_point's choice among the importances values[i * stride] of sum total.
  uint32_t pick_among(float u, const float* values, uint32_t stride, float total, float* pmf, float* sum) const;
  float pmf_per_point(uint32_t i, const SurfacePoint& ref, float sum) const;
  /// Whether lights are weighed at each point (else by power).
  bool per_point() const { return importance_.size() > 0; }

  LightImportance importance_;        ///< empty unless picking per point
  PiecewiseConstant1D distribution_;  ///< by power
  /// One light: picked with probability exactly 1 (the distribution would give its weight
  /// over their sum, rounded to float: 1 - 2^-24 for some weights).
  bool single_ = false;
};

[[gnu::always_inline]] inline uint32_t LightPicker::pick_per_point(float u, const SurfacePoint& ref, float* pmf,
                                     float* sum) const {
  std::array<float, kMaxPerPoint> importance;
  const float total = importance_.evaluate_all(ref.p, ref.ng, importance.data());
  return pick_among(u, importance.data(), 1, total, pmf, sum);
}

[[gnu::always_inline]] inline uint32_t LightPicker::pick_among(float u, const float* values, uint32_t stride,
                                                               float total, float* pmf, float* sum) const {
  if (sum) *sum = total;
  *pmf = 0;
  if (!(total > 0)) return 0;
  // The first light whose cumulative importance exceeds u * total; lights of importance 0 are
  // never chosen (if rounding carries u * total past the sum, the last light with any).
  const float target = u * total;
  float cumulative = 0;
  uint32_t chosen = 0;
  for (uint32_t i = 0; i < importance_.size(); ++i) {
    const float importance = values[i * stride];
    if (!(importance > 0)) continue;
    chosen = i;
    cumulative += importance;
    if (target < cumulative) break;
  }
  *pmf = values[chosen * stride] / total;
  return chosen;
}

}  // namespace tessera
