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

RgbImage downsample(const RgbImage& image, int k) {
  if (image.width % k != 0 || image.height % k != 0) throw std::invalid_argument("downsample: size");
  RgbImage out;
  out.width = image.width / k;
  out.height = image.height / k;
  out.rgb.assign(size_t(out.width) * size_t(out.height) * 3, 0.0f);
  for (int y = 0; y < out.height; ++y) {
    for (int x = 0; x < out.width; ++x) {
      for (int c = 0; c < 3; ++c) {
        double sum = 0;
        for (int j = 0; j < k; ++j) {
          for (int i = 0; i < k; ++i) {
            sum += image.rgb[(size_t(y * k + j) * size_t(image.width) + size_t(x * k + i)) * 3 + size_t(c)];
          }
        }
        out.rgb[(size_t(y) * size_t(out.width) + size_t(x)) * 3 + size_t(c)] = float(sum / (k * k));
      }
    }
  }
  return out;
}

}  // namespace tessera::test
