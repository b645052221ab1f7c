// The pixel reconstruction filter, applied by filter importance sampling.
//
// Rather than splatting each camera sample into every pixel its filter footprint covers (as
// Mitsuba's ImageBlock does), Tessera draws the sample's film offset from the filter itself
// (pbrt-v4's FilterSampler): the offset's density is proportional to the filter, so every
// sample counts with weight 1 in the one pixel it was drawn for. Pixels then never share
// samples, so tiles and sample ranges stay independent and the accumulation format is unchanged
// (docs/renderer.md, "Pixel filters").
//
// Every filter is separable: f(x, y) = f(x) f(y); x and y are drawn independently from the same
// one-dimensional profile.
#pragma once

#include <vector>

#include <glm/vec2.hpp>

#include "scene/scene.h"

namespace tessera {

/// Draws film positions of camera samples from a pixel's reconstruction filter. Built once per
/// job from Scene::film.filter; sample() and film_position() are const, thread-safe and pure
/// functions of their arguments: the same bits on every machine (no libm call at render time:
/// the tent uses sqrt, which IEEE 754 rounds exactly; the gaussian a table built with plain
/// arithmetic).
class PixelFilterSampler {
 public:
  /// The filter's one-dimensional profile f(x), |x| in pixels, unnormalised as Mitsuba's
  /// rfilters define it: box 1 inside the radius; tent 1 - |x| / radius; gaussian
  /// exp(-x^2 / (2 stddev^2)) minus its value at the radius, clamped at 0. Zero outside
  /// [-radius, radius].
  static double profile(const PixelFilter& filter, double x);

  /// Throws SceneError("film.filter.radius: ...") when radius or (gaussian) stddev is not
  /// finite and > 0.
  explicit PixelFilterSampler(const PixelFilter& filter);

  /// Offset from the pixel centre, in pixels, each component in [-radius, radius], drawn from
  /// u in [0, 1)^2 with density f(x) f(y) / (integral of f)^2. Monotonic in each component of u,
  /// so stratification of u carries over to the offsets.
  glm::vec2 sample(glm::vec2 u) const;

  /// Film position (pixels, origin at the image's top-left corner) of the camera sample of pixel
  /// (x, y) drawn from u: the pixel centre plus sample(u). The box filter of radius 0.5 returns
  /// exactly (x + u.x, y + u.y), the film position Tessera used before filters existed, so
  /// images rendered with it keep their bits.
  glm::vec2 film_position(int x, int y, glm::vec2 u) const;

  /// One component of sample(), in double precision: the offset x in [-radius, radius] with
  /// P(offset <= x) = u under the density f(x) / integral of f (tabulated for the gaussian).
  double sample_1d(double u) const;

  const PixelFilter& filter() const { return filter_; }

 private:
  double sample_table(double u) const;

  PixelFilter filter_;
  /// Gaussian only: the profile tabulated at kTableSegments + 1 evenly spaced nodes over
  /// [-radius, radius], normalised to a density (pdf_) that is linear between nodes, and its
  /// integral at each node (cdf_, from 0 to exactly 1).
  std::vector<double> pdf_, cdf_;
  double dx_ = 0;
};

}  // namespace tessera
