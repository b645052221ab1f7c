// Lossless wire/storage format of an Accumulation (zstd-compressed, versioned, checked).
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

#include "accum/accumulation.h"

namespace tessera {

class CodecError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Encodes losslessly: a decoded result compares equal bit for bit.
std::string encode_accumulation(const Accumulation& acc);

/// Decodes what encode_accumulation wrote. Throws CodecError naming the problem on truncated,
/// corrupt or inconsistent input (never reads out of bounds, never allocates more than the
/// header's rectangle needs, refuses rectangles above `max_pixels`).
Accumulation decode_accumulation(std::string_view bytes, int64_t max_pixels = int64_t(1) << 26);

}  // namespace tessera
