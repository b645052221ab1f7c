// The sRGB transfer function, as Mitsuba decodes 8- and 16-bit images.
#pragma once

#include <cmath>

namespace tessera {

/// Linear value of an sRGB-encoded value v in [0, 1] (IEC 61966-2-1).
inline double srgb_to_linear(double v) {
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

}  // namespace tessera
