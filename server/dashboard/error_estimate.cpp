#include "dashboard/error_estimate.h"

#include <algorithm>
#include <cmath>

namespace tessera::server {

ErrorEstimate ErrorEstimate::of(const Accumulation& a) {
  ErrorEstimate e;
  for (size_t i = 0; i < a.pixels(); ++i) {
    const double n = a.count[i];
    if (n < 2) continue;
    const double mean = luminance(a.rgb[3 * i], a.rgb[3 * i + 1], a.rgb[3 * i + 2]) / n;
    // Unbiased sample variance from the two sums; rounding can make it slightly negative.
    const double variance = std::max(0.0, (a.lum2[i] - n * mean * mean) / (n - 1));
    e.sum_variance_of_mean += variance / n;
    e.sum_mean_luminance += mean;
    ++e.pixels;
  }
  return e;
}

void ErrorEstimate::add(const ErrorEstimate& other) {
  sum_variance_of_mean += other.sum_variance_of_mean;
  sum_mean_luminance += other.sum_mean_luminance;
  pixels += other.pixels;
}

std::optional<double> ErrorEstimate::relative_error() const {
  if (pixels == 0 || !(sum_mean_luminance > 0)) return std::nullopt;
  const double rms_standard_error = std::sqrt(sum_variance_of_mean / double(pixels));
  return rms_standard_error / (sum_mean_luminance / double(pixels));
}

}  // namespace tessera::server
