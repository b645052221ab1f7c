// Lossless wire/storage format of an Accumulation (zstd-compressed, versioned, checked).
#pragma once

#include <memory>
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
  /// zstd level 3.
  standard,
  /// zstd level -1: what workers upload (worker/farm/farm_worker.cpp, kUploadEffort) and the
  /// server's checkpoints of merged tiles. A third of level 3's compression instructions and
  /// fewer to decode, for about 1 % more bytes on a many-sample tile (BENCHMARKS.md, "The
  /// farm's overhead on one job" and "What a result and a job cost the server, counted").
  fast,
};

/// Encodes losslessly: a decoded result compares equal bit for bit. Deterministic: the same
/// accumulation and effort give the same bytes. Uses the calling thread's AccumulationEncoder.
std::string encode_accumulation(const Accumulation& acc,
                                CodecEffort effort = CodecEffort::standard);

/// encode_accumulation with a zstd compression context kept from one call to the next: a new
/// context per call allocated and set up its tables (about 1 MB at level 3 for a 64-px tile)
/// every time (0.5 M of a 4.5 M-instruction encode; BENCHMARKS.md, "What a result and a job
/// cost the server, counted"). The bytes do not depend on earlier calls. Not thread-safe: one per
/// thread, or one used under a lock (the server's merger encodes checkpoints under its store
/// lock with one, so its many gRPC threads keep no context each).
class AccumulationEncoder {
 public:
  AccumulationEncoder();
  ~AccumulationEncoder();
  AccumulationEncoder(const AccumulationEncoder&) = delete;
  AccumulationEncoder& operator=(const AccumulationEncoder&) = delete;

  std::string encode(const Accumulation& acc, CodecEffort effort = CodecEffort::standard);

 private:
  struct Context;
  std::unique_ptr<Context> context_;
};

/// Decodes what encode_accumulation wrote. Throws CodecError naming the problem on truncated,
/// corrupt or inconsistent input (never reads out of bounds, never allocates more than the
/// header's rectangle needs, refuses rectangles above `max_pixels`).
Accumulation decode_accumulation(std::string_view bytes, int64_t max_pixels = int64_t(1) << 26);

}  // namespace tessera
