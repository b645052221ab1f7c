#pragma once

#include <glm/vec3.hpp>

#include "image/image_output.h"

namespace tessera::test {

/// Mean per channel over all pixels.
glm::dvec3 channel_means(const RgbImage& image);
/// Root-mean-square difference over all pixels and channels; images must have the same size.
double rmse(const RgbImage& a, const RgbImage& b);
/// The image averaged over k x k blocks (width and height must be multiples of k): noise falls
/// by k while a bias over a region stays, so comparisons of block means catch local bias.
RgbImage downsample(const RgbImage& image, int k);

}  // namespace tessera::test
