#pragma once

#include <glm/vec3.hpp>

#include "image/image_output.h"

namespace tessera::test {

/// Mean per channel over all pixels.
glm::dvec3 channel_means(const RgbImage& image);
/// Root-mean-square difference over all pixels and channels; images must have the same size.
double rmse(const RgbImage& a, const RgbImage& b);

}  // namespace tessera::test
