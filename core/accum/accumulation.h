// The result of rendering samples into a tile: per-pixel double sums, merged in batch order.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "accum/tile_rect.h"

namespace tessera {

/// A sample that produced NaN or Inf radiance and was dropped, kept so it can be replayed alone.
struct DroppedSample {
  int x = 0, y = 0;              ///< image pixel
  uint32_t sample_index = 0;     ///< global sample index within the pixel
  bool operator==(const DroppedSample&) const = default;
};

/// Per-pixel sums over a set of samples of one tile. Pixels are row-major within `rect`.
/// Sums are in double and divided only at read-out. A dropped (NaN/Inf)
/// sample adds nothing, not even to `count`.
struct Accumulation {
  TileRect rect;
  std::vector<double> rgb;       ///< 3 per pixel: sums of linear R, G, B radiance
  std::vector<double> lum2;      ///< per pixel: sum of squared luminance (Rec. 709 Y)
  std::vector<uint32_t> count;   ///< per pixel: samples summed
  uint64_t nan_dropped = 0;      ///< samples dropped because a component was NaN
  uint64_t inf_dropped = 0;      ///< samples dropped because a component was +-Inf
  std::vector<DroppedSample> dropped_examples;  ///< the first few dropped samples, at most kMaxDroppedExamples

  static constexpr size_t kMaxDroppedExamples = 16;

  Accumulation() = default;
  explicit Accumulation(TileRect r);

  size_t pixels() const { return count.size(); }

  /// Adds `next` (the following batch of the same tile) into this one, pixel by pixel:
  /// this += next. The determinism contract needs callers to merge batches in batch order.
  /// Throws std::invalid_argument when the rectangles differ.
  void merge(const Accumulation& next);

  bool operator==(const Accumulation&) const = default;
};

/// Rec. 709 luminance of linear RGB.
inline double luminance(double r, double g, double b) {
  return 0.2126 * r + 0.7152 * g + 0.0722 * b;
}

}  // namespace tessera
