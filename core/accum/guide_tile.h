// The denoiser's guides (denoise/denoiser.h) of one tile: per pixel, the sums over its samples
// of the albedo and the shading normal that each camera sample found (the worker's
// render/guides/guide_tracer.h), summed in sample order and merged batch by batch in batch
// order, as a tile's colour is, so that they depend only on (seed, pixel, sample) and never on
// threads or tiling. In core: the server merges a farm job's guides (server/job_guides.h).
#pragma once

#include <cstdint>
#include <vector>

#include "accum/tile_rect.h"
#include "image/image_output.h"

namespace tessera {

/// Guides come from a pixel's first kGuideSamples samples at most: by then they have converged
/// (exact albedo and normals on Lambertian surfaces, antialiased edges), and a long render
/// does not pay for them again and again.
inline constexpr uint32_t kGuideSamples = 64;

struct GuideTile {
  TileRect rect;
  std::vector<double> albedo;   ///< 3 per pixel, row-major in the tile: sums
  std::vector<double> normal;   ///< 3 per pixel: sums of unit (or zero) normals
  std::vector<uint32_t> count;  ///< samples per pixel

  GuideTile() = default;
  explicit GuideTile(const TileRect& r);
  /// Adds `other`'s sums (the same rect; a default-constructed tile takes `other` whole).
  void merge(const GuideTile& other);
};

/// The guide images (the image's size; pixels no tile covers stay 0): mean albedo, and mean
/// normal (not renormalised: a pixel whose samples saw different surfaces keeps their average,
/// as OIDN expects).
struct GuideImages {
  RgbImage albedo, normal;
};
GuideImages resolve_guides(int width, int height, const std::vector<GuideTile>& tiles);

/// EXR channels albedo.R, albedo.G, albedo.B, N.X, N.Y, N.Z of `guides` (ExtraChannel order).
std::vector<ExtraChannel> guide_channels(const GuideImages& guides);

}  // namespace tessera
