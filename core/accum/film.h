// Assembling an image from merged tile accumulations.
#pragma once

#include <vector>

#include "accum/accumulation.h"
#include "image/image_output.h"

namespace tessera {

/// The image of mean radiance per pixel: sums / count, 0 where a pixel has no samples.
/// Tiles may be given in any order; pixels they do not cover stay 0.
RgbImage resolve_image(int width, int height, const std::vector<Accumulation>& tiles);

/// Writes one tile's mean radiance into `image` (sized by resolve_image), leaving pixels without
/// samples as they are: what resolve_image does for each tile, so that a caller holding many
/// tiles encoded can decode and resolve them one at a time.
void resolve_into(RgbImage& image, const Accumulation& tile);

}  // namespace tessera

namespace tessera {

/// The estimated relative error of the mean luminance over a set of pixels:
/// sqrt(mean over pixels of the variance of each pixel's mean luminance) / max(mean luminance,
/// 1e-4), from the sums of luminance and squared luminance (the noise rule, docs/accuracy.md).
/// Pixels with fewer than 2 samples are left out; returns 0 when no pixel has 2.
double estimate_relative_error(const std::vector<Accumulation>& tiles);

/// The same estimate over one tile's pixels: the noise rule's per-tile error (stopping_rule.h).
double estimate_relative_error(const Accumulation& tile);

}  // namespace tessera
