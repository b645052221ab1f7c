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

/// How hard zstd works on the payload. Either gives the same format, read by the same
/// decode_accumulation (any zstd level decodes alike), and the same sums bit for bit.
enum class CodecEffort {
  /// zstd level 3: what workers upload (each result crosses the network and the store once).
  standard,
  /// zstd level -1: the server's checkpoints of merged tiles, encoded on the server's CPU and
  /// never sent anywhere. A third of level 3's compression instructions and fewer to decode,
  /// for about 1 % more bytes on a many-sample tile (BENCHMARKS.md, issue 14 sections of
  /// farm13 and farm15).
  fast,
};

/// Encodes losslessly: a decoded result compares equal bit for bit. Deterministic: the same
/// accumulation and effort give the same bytes.
std::string encode_accumulation(const Accumulation& acc,
                                CodecEffort effort = CodecEffort::standard);

/// Decodes what encode_accumulation wrote. Throws CodecError naming the problem on truncated,
/// corrupt or inconsistent input (never reads out of bounds, never allocates more than the
/// header's rectangle needs, refuses rectangles above `max_pixels`).
Accumulation decode_accumulation(std::string_view bytes, int64_t max_pixels = int64_t(1) << 26);

}  // namespace tessera
