#include "accum/film.h"

#include <algorithm>
#include <cmath>

namespace tessera {

RgbImage resolve_image(int width, int height, const std::vector<Accumulation>& tiles) {
  RgbImage image;
  image.width = width;
  image.height = height;
  image.rgb.assign(size_t(width) * size_t(height) * 3, 0.0f);
  for (const Accumulation& acc : tiles) resolve_into(image, acc);
  return image;
}

void resolve_into(RgbImage& image, const Accumulation& acc) {
  const TileRect& r = acc.rect;
  for (int y = r.y0; y < r.y1; ++y) {
    for (int x = r.x0; x < r.x1; ++x) {
      const size_t i = size_t(y - r.y0) * size_t(r.width()) + size_t(x - r.x0);
      const uint32_t n = acc.count[i];
      if (n == 0) continue;
      float* out = &image.rgb[(size_t(y) * size_t(image.width) + size_t(x)) * 3];
      for (int c = 0; c < 3; ++c) out[c] = float(acc.rgb[i * 3 + c] / double(n));
    }
  }
}

}  // namespace tessera

namespace tessera {

namespace {

/// Sums over the pixels with at least 2 samples, in pixel order (the order is fixed: the
/// estimate decides which batches a noise tile gets, so it must be bit-reproducible).
struct ErrorSums {
  double variance_sum = 0, mean_sum = 0;
  uint64_t pixels = 0;

  void add(const Accumulation& acc) {
    for (size_t i = 0; i < acc.count.size(); ++i) {
      const double n = acc.count[i];
      if (n < 2) continue;
      const double mean = luminance(acc.rgb[i * 3], acc.rgb[i * 3 + 1], acc.rgb[i * 3 + 2]) / n;
      const double second = acc.lum2[i] / n;
      // Unbiased sample variance of one sample, then of the mean of n samples.
      const double sample_var = std::max(0.0, (second - mean * mean) * n / (n - 1));
      variance_sum += sample_var / n;
      mean_sum += mean;
      ++pixels;
    }
  }

  double relative_error() const {
    if (pixels == 0) return 0;
    const double mean_lum = mean_sum / double(pixels);
    return std::sqrt(variance_sum / double(pixels)) / std::max(mean_lum, 1e-4);
  }
};

}  // namespace

double estimate_relative_error(const std::vector<Accumulation>& tiles) {
  ErrorSums sums;
  for (const Accumulation& acc : tiles) sums.add(acc);
  return sums.relative_error();
}

double estimate_relative_error(const Accumulation& tile) {
  ErrorSums sums;
  sums.add(tile);
  return sums.relative_error();
}

}  // namespace tessera
