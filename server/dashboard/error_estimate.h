// The estimated relative error of a rendered region, from the per-pixel sums every accumulation
// carries (sum of luminance via RGB, sum of squared luminance, count). For each pixel with n >= 2
// samples the variance of its mean luminance is s² / n, with s² the unbiased sample variance;
// the region's relative error is sqrt(mean over pixels of s² / n) / (mean over pixels of the mean
// luminance): the RMS standard error of a pixel relative to the region's brightness. Regions add
// (tiles into a job) before the division.
#pragma once

#include <cstdint>
#include <optional>

#include "accum/accumulation.h"

namespace tessera::server {

struct ErrorEstimate {
  double sum_variance_of_mean = 0;  ///< sum over pixels of s² / n
  double sum_mean_luminance = 0;    ///< sum over pixels of the mean luminance
  uint64_t pixels = 0;              ///< pixels with at least two samples

  static ErrorEstimate of(const Accumulation& accumulation);
  void add(const ErrorEstimate& other);
  /// nullopt when no pixel has two samples yet, or the region is black (error undefined).
  std::optional<double> relative_error() const;
};

}  // namespace tessera::server
