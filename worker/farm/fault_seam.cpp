#include "fault_seam.h"

#include <bit>
#include <cstdint>
#include <cstdlib>
#include <cstring>

namespace tessera::farm {

bool fault_flip_bit_requested() {
  static const bool requested = [] {
    const char* value = std::getenv("TESSERA_FAULT_FLIP_BIT");
    return value != nullptr && std::strcmp(value, "1") == 0;
  }();
  return requested;
}

Accumulation with_one_bit_flipped(Accumulation result) {
  if (!result.rgb.empty()) {
    result.rgb[0] = std::bit_cast<double>(std::bit_cast<uint64_t>(result.rgb[0]) ^ uint64_t(1));
  }
  return result;
}

}  // namespace tessera::farm
