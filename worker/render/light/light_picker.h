// Choosing which light a shading point samples.
#pragma once

#include <cstdint>
#include <vector>

#include "render/light/light_bounds.h"
#include "render/light/piecewise_constant.h"
#include "render/ray_offset.h"

namespace tessera {

/// Picks one light per shading point. With 2 to kMaxPerPoint lights, with probability
/// proportional to each light's importance at the point (LightBounds::importance with the
/// point's geometric normal: power, distance and the cosine bounds at both ends, no
/// visibility), so that near lights facing the point are picked more often and lights that
/// cannot reach it (one-sided lights seen from behind) not at all. With more lights (where
/// evaluating every light at every point would cost more than it saves, and a light BVH is
/// future work) and with one, by power alone (pbrt's PowerLightSampler); when every power is 0,
/// uniformly.
class LightPicker {
 public:
  static constexpr size_t kMaxPerPoint = 16;

  /// One bounds and one power (finite, >= 0) per light, in the same order.
  LightPicker(std::vector<LightBounds> bounds, const std::vector<double>& powers);

  /// Index of the chosen light from u in [0, 1), its probability in `pmf` (> 0). When no
  /// light can reach ref (every importance 0), returns 0 with *pmf = 0. Must not be called
  /// without lights.
  uint32_t pick(float u, const SurfacePoint& ref, float* pmf) const {
    // By power inline: a scene of one light pays nothing for picking per point.
    if (!per_point()) return distribution_.sample_discrete(u, pmf);
    return pick_per_point(u, ref, pmf);
  }
  /// The probability pick() gives light i at ref (bit for bit the pmf pick() reports).
  float pmf(uint32_t i, const SurfacePoint& ref) const {
    if (!per_point()) return distribution_.pmf(i);
    return pmf_per_point(i, ref);
  }

 private:
  uint32_t pick_per_point(float u, const SurfacePoint& ref, float* pmf) const;
  float pmf_per_point(uint32_t i, const SurfacePoint& ref) const;
  /// Whether lights are weighed at each point (else by power).
  bool per_point() const { return !bounds_.empty(); }
  /// Every light's importance at ref into `importance`; returns their sum.
  double importances(const SurfacePoint& ref, double* importance) const;

  std::vector<LightBounds> bounds_;  ///< empty unless picking per point
  PiecewiseConstant1D distribution_;  ///< by power
};

}  // namespace tessera
