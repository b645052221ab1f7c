// Choosing which light a shading point samples.
#pragma once

#include <cstdint>
#include <vector>

#include "render/light/piecewise_constant.h"
#include "render/ray_offset.h"

namespace tessera {

/// Picks one light per shading point with probability proportional to its power (pbrt's
/// PowerLightSampler). The shading point is an argument so that picking by contribution at the
/// point can replace this without touching the callers. When every power is 0 the lights are
/// picked uniformly.
class LightPicker {
 public:
  /// powers: finite and >= 0, one per light.
  explicit LightPicker(const std::vector<double>& powers);

  /// Index of the chosen light from u in [0, 1), its probability in `pmf` (> 0).
  /// Must not be called without lights.
  uint32_t pick(float u, const SurfacePoint& ref, float* pmf) const;
  /// The probability pick() gives light i at ref.
  float pmf(uint32_t i, const SurfacePoint& ref) const;

 private:
  PiecewiseConstant1D distribution_;
};

}  // namespace tessera
