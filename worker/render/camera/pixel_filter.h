// The pixel reconstruction filter, applied by filter importance sampling.
//
// Rather than splatting each camera sample into every pixel its filter footprint covers (as
// Mitsuba's ImageBlock does), Tessera draws the sample's film offset from the filter itself
// (pbrt-v4's FilterSampler): the offset's density is proportional to the filter's magnitude,
// so every sample counts in the one pixel it was drawn for, with weight 1 where the filter is
// never negative and with the filter's sign times a constant where it has negative lobes
// (mitchell, lanczos). Pixels then never share samples, so tiles and sample ranges stay
// independent and the accumulation format is unchanged (docs/renderer.md, "Pixel filters").
//
// Every filter is separable: f(x, y) = f(x) f(y); x and y are drawn independently from the same
// one-dimensional profile.
#pragma once

#include <vector>

#include <glm/vec2.hpp>

#include "scene/scene.h"

namespace tessera {

/// A camera sample's place on the film and the weight it counts with in its pixel.
struct FilmSample {
  glm::vec2 position;  ///< pixels, origin at the image's top-left corner
  double weight;       ///< 1 for filters that are never negative
};

/// Draws film positions of camera samples from a pixel's reconstruction filter. Built once per
/// job from Scene::film.filter; sample(), film_position() and film_sample() are const,
/// thread-safe and pure functions of their arguments: the same bits on every machine (no libm
/// call at render time: the tent uses sqrt, which IEEE 754 rounds exactly; the other curved
/// filters a table built with plain arithmetic).
class PixelFilterSampler {
 public:
  /// The filter's one-dimensional profile f(x), |x| in pixels, unnormalised as Mitsuba's
  /// rfilters define it: box 1 inside the radius; tent 1 - |x| / radius; gaussian
  /// exp(-x^2 / (2 stddev^2)) minus its value at the radius, clamped at 0; mitchell
  /// Mitchell and Netravali's cubic in |x| with B and C (negative for 1 < |x| < 2 at the
  /// defaults); lanczos sinc(x) sinc(x / lobes) (negative in every other lobe). Zero outside
  /// [-radius, radius].
  static double profile(const PixelFilter& filter, double x);

  /// Throws SceneError("film.filter.<key>: ...") when radius or (gaussian) stddev is not
  /// finite and > 0, or (mitchell) B or C is not finite, or the filter integrates to zero or
  /// less (a mitchell whose negative lobes outweigh its positive part cannot be normalised).
  explicit PixelFilterSampler(const PixelFilter& filter);

  /// Whether samples carry weights other than 1 (the filter has negative lobes): the renderer
  /// multiplies each sample's estimate by FilmSample::weight only then, so the other filters'
  /// images keep their bits.
  bool signed_weights() const { return signed_; }

  /// Film position and weight of the camera sample of pixel (x, y) drawn from u: the position
  /// is film_position(x, y, u); the weight w makes w L an unbiased estimate of the pixel's
  /// filtered value, integral f L / integral f (the normalised filter Mitsuba's film computes):
  /// w = f(dx) f(dy) / (pdf(dx) pdf(dy) (integral of f)^2) with pdf the density the offset was
  /// drawn from, proportional to |f|. So w = +-(integral |f| / integral f)^2, its sign f's.
  FilmSample film_sample(int x, int y, glm::vec2 u) const;

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
  /// P(offset <= x) = u under the density |f(x)| / integral of |f| (tabulated for the gaussian,
  /// mitchell and lanczos). With `weight`, also sets the offset's one-dimensional weight
  /// f(x) / (pdf(x) integral f), so that film_sample's weight is the product of two.
  double sample_1d(double u, double* weight = nullptr) const;

  const PixelFilter& filter() const { return filter_; }

 private:
  double sample_table(double u, double* weight) const;

  PixelFilter filter_;
  /// Tabulated filters (gaussian, mitchell, lanczos): the profile at kTableSegments + 1 evenly
  /// spaced nodes over [-radius, radius]. The filter sampled is the profile interpolated
  /// linearly between nodes (within 1e-4 of its peak: PixelFilter.SampledDensityEqualsTheFilter);
  /// its magnitude, normalised, is the density pdf_ (linear between nodes, as |f| at the nodes),
  /// cdf_ its integral at each node (from 0 to exactly 1), value_ the signed profile at the
  /// nodes divided by its integral.
  std::vector<double> pdf_, cdf_, value_;
  double dx_ = 0;
  bool signed_ = false;
};

}  // namespace tessera
