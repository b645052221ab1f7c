#include "image_compare.h"

#include <cmath>
#include <stdexcept>

namespace tessera::test {

glm::dvec3 channel_means(const RgbImage& image) {
  glm::dvec3 sum(0.0);
  const size_t n = size_t(image.width) * size_t(image.height);
  for (size_t i = 0; i < n; ++i) {
    sum += glm::dvec3(image.rgb[i * 3], image.rgb[i * 3 + 1], image.rgb[i * 3 + 2]);
  }
  return sum / double(n);
}

double rmse(const RgbImage& a, const RgbImage& b) {
  if (a.width != b.width || a.height != b.height) throw std::invalid_argument("rmse: sizes differ");
  double sum = 0;
  for (size_t i = 0; i < a.rgb.size(); ++i) {
    const double d = double(a.rgb[i]) - double(b.rgb[i]);
    sum += d * d;
  }
  return std::sqrt(sum / double(a.rgb.size()));
}

}  // namespace tessera::test
