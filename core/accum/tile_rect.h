#pragma once

#include <cstdint>

namespace tessera {

/// A rectangle of image pixels [x0, x1) x [y0, y1); row 0 is the top of the image.
struct TileRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;

  int width() const { return x1 - x0; }
  int height() const { return y1 - y0; }
  int64_t pixel_count() const { return int64_t(width()) * height(); }
  bool operator==(const TileRect&) const = default;
};

}  // namespace tessera
