// Doubles rounded to the float on one side of them, for bounding boxes handed to Embree (which
// takes floats): a box rounded outwards this way still holds every point of the double one.
#pragma once

#include <cmath>

namespace tessera {

/// The largest float <= x.
inline float round_down(double x) {
  const float f = float(x);
  return double(f) > x ? std::nextafter(f, -INFINITY) : f;
}

/// The smallest float >= x.
inline float round_up(double x) {
  const float f = float(x);
  return double(f) < x ? std::nextafter(f, INFINITY) : f;
}

}  // namespace tessera
