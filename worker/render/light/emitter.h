// Area lights: sampling points on emitting shapes by area.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "render/geometry.h"
#include "render/ray_offset.h"

namespace tessera {

/// A point sampled on an emitter.
struct EmitterSample {
  SurfacePoint sp;        ///< the point, its error bound and its front-facing unit normal
  float pdf_area = 0;     ///< density with respect to area on the emitter (1 / its area)
};

/// One emitting shape. Points are uniform over its surface area.
class Emitter {
 public:
  /// `geometry` must outlive the emitter.
  explicit Emitter(const Geometry& geometry);

  /// Samples a point uniformly by area, from u in [0,1)^2.
  EmitterSample sample(glm::vec2 u) const;

  float area() const { return area_; }
  /// Emitted flux (luminance-weighted), the light's share of light selection.
  float power() const;
  const Geometry& geometry() const { return *geometry_; }

 private:
  const Geometry* geometry_;
  std::vector<float> triangle_cdf_;  ///< cumulative triangle areas, normalised, last = 1
  float area_ = 0;
};

/// Picks one emitter per shading point, with probability proportional to its power.
class LightSelector {
 public:
  explicit LightSelector(const std::vector<Emitter>& emitters);

  /// Returns the index of the chosen emitter and its probability; u in [0,1).
  /// Must not be called when there are no emitters.
  uint32_t pick(float u, float* pmf) const;
  float pmf(uint32_t index) const { return pmf_[index]; }

 private:
  std::vector<float> cdf_;
  std::vector<float> pmf_;
};

}  // namespace tessera
