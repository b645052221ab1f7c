// The accumulation codec: a small fixed header, then one zstd frame with the payload.
//
// Layout of format version 1 (every integer little-endian, whatever the host):
//
//   offset  size  field
//        0     5  magic "TSACC"
//        5     2  u16 format version (1)
//        7    16  i32 rect x0, y0, x1, y1
//       23     8  u64 rgb length   (must be 3 * rect pixels)
//       31     8  u64 lum2 length  (must be rect pixels)
//       39     8  u64 count length (must be rect pixels)
//       47     4  u32 dropped example count (at most Accumulation::kMaxDroppedExamples)
//       51     .  one zstd frame, content size and XXH64 checksum included, holding:
//                   the 44 header bytes [7, 51) again, so the checksum covers them too
//                   u64 nan_dropped, u64 inf_dropped
//                   per dropped example: i32 x, i32 y, u32 sample_index
//                   rgb, lum2: IEEE-754 doubles, byte-shuffled (see shuffle_planes)
//                   count: u32, byte-shuffled
//
// The header alone sizes everything, so a decoder checks the sizes (against max_pixels and
// against the frame's declared content size) before it allocates or decompresses anything.
#include "accum/accumulation_codec.h"

#include <zstd.h>

#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

namespace tessera {
namespace {

constexpr std::array<char, 5> kMagic = {'T', 'S', 'A', 'C', 'C'};
constexpr uint16_t kVersion = 1;
constexpr size_t kSizingOffset = 7;  // where the rect starts
constexpr size_t kHeaderSize = 51;   // magic .. dropped example count
constexpr size_t kSizingSize = kHeaderSize - kSizingOffset;
constexpr size_t kDroppedExampleSize = 12;
constexpr size_t kBytesPerPixel = 3 * 8 + 8 + 4;  // rgb, lum2, count
constexpr int kZstdLevelStandard = 3;
constexpr int kZstdLevelFast = -1;

static_assert(std::numeric_limits<double>::is_iec559, "the format stores IEEE-754 doubles");

// ---- little-endian writing and bounds-checked reading ----
// Every value is split into bytes by shifts (doubles through std::bit_cast), never by copying
// memory, so the bytes are little-endian whatever the host's byte order.

template <typename T>
void put_le(std::string& out, T value) {
  using U = std::make_unsigned_t<T>;
  const U bits = static_cast<U>(value);
  for (size_t i = 0; i < sizeof(T); ++i) out.push_back(char(uint8_t(bits >> (8 * i))));
}

/// Reads little-endian fields from a byte range; throws CodecError instead of overrunning it.
class Reader {
 public:
  Reader(const uint8_t* data, size_t size, const char* what)
      : p_(data), end_(data + size), what_(what) {}

  template <typename T>
  T get() {
    using U = std::make_unsigned_t<T>;
    const uint8_t* bytes = take(sizeof(T));
    U bits = 0;
    for (size_t i = 0; i < sizeof(T); ++i) bits |= U(bytes[i]) << (8 * i);
    return static_cast<T>(bits);
  }

  const uint8_t* take(size_t n) {
    if (size_t(end_ - p_) < n) {
      throw CodecError(std::string("accumulation codec: truncated ") + what_);
    }
    const uint8_t* at = p_;
    p_ += n;
    return at;
  }

  size_t left() const { return size_t(end_ - p_); }

 private:
  const uint8_t* p_;
  const uint8_t* end_;
  const char* what_;
};

// ---- byte shuffling ----
//
// Sums of noisy radiance share their sign, exponent and leading mantissa bits from pixel to
// pixel, while their low mantissa bytes are noise. Grouping byte k of every value together
// (byte plane by byte plane) puts the compressible bytes side by side for zstd. Measured with
// zstd 1.5.4 level 3 on a 64x64 tile of noisy float samples summed in double (the generator of
// accumulation_codec_test.cpp, CompressionRatio), bytes per pixel out of 36 raw:
//   samples per pixel           1      16     256
//   shuffled                 15.8    22.4    25.2
//   not shuffled             15.5    24.2    27.1
//   30% empty rows, shuffled 11.1    15.7    17.6  (not shuffled: 10.7, 16.9, 19.0)
// Shuffling wins 7% on the batches a farm sends (many samples each) and loses 2-3% only at one
// sample per pixel, so it is always on. Per-channel planes (RRR..GGG..BBB) before shuffling
// made no measurable difference. Encoding takes about 0.25 ms per 64x64 tile, decoding 0.12 ms.

/// Transposes an 8x8 matrix of bytes held as eight little-endian rows: afterwards byte j of
/// rows[k] is what byte k of rows[j] was. Swaps 1-byte, then 2-byte, then 4-byte blocks between
/// rows 1, 2 and 4 apart (12 shift-xor-mask swaps for 64 bytes). Shuffling 8 doubles into 8
/// planes, or back, is this transpose: row k = plane k's bytes of the 8 values, row j = value j.
inline void transpose8x8(uint64_t rows[8]) {
  // Written out (not looped over levels): a loop with the shift and mask as variables is not
  // unrolled at -O2 and cost 300 instructions per call instead of about 80.
  const auto swap = [](uint64_t& upper, uint64_t& lower, int shift, uint64_t mask) {
    const uint64_t t = ((upper >> shift) ^ lower) & mask;
    lower ^= t;
    upper ^= t << shift;
  };
  constexpr uint64_t k1 = 0x00FF00FF00FF00FFull, k2 = 0x0000FFFF0000FFFFull,
                     k4 = 0x00000000FFFFFFFFull;
  swap(rows[0], rows[1], 8, k1);
  swap(rows[2], rows[3], 8, k1);
  swap(rows[4], rows[5], 8, k1);
  swap(rows[6], rows[7], 8, k1);
  swap(rows[0], rows[2], 16, k2);
  swap(rows[1], rows[3], 16, k2);
  swap(rows[4], rows[6], 16, k2);
  swap(rows[5], rows[7], 16, k2);
  swap(rows[0], rows[4], 32, k4);
  swap(rows[1], rows[5], 32, k4);
  swap(rows[2], rows[6], 32, k4);
  swap(rows[3], rows[7], 32, k4);
}

/// Doubles' bits in 8 byte planes (put) or from them (get), 8 values at a time through
/// transpose8x8 on a little-endian host: the byte-by-byte loops below cost about 64
/// instructions per double, this about 12 (callgrind; BENCHMARKS.md, "What a result and a job
/// cost the server, counted"). Returns how many values it did (a multiple of 8; 0 on other
/// hosts): the caller does the rest byte by byte. The bytes are the same either way.
size_t put_planes8(char* planes, size_t n, const double* values) {
  if constexpr (std::endian::native != std::endian::little) return 0;
  const size_t whole = n - n % 8;
  for (size_t i = 0; i < whole; i += 8) {
    uint64_t rows[8];
    for (int j = 0; j < 8; ++j) rows[j] = std::bit_cast<uint64_t>(values[i + j]);
    transpose8x8(rows);
    for (int k = 0; k < 8; ++k) std::memcpy(planes + size_t(k) * n + i, &rows[k], 8);
  }
  return whole;
}

size_t get_planes8(const uint8_t* planes, size_t n, double* values) {
  if constexpr (std::endian::native != std::endian::little) return 0;
  const size_t whole = n - n % 8;
  for (size_t i = 0; i < whole; i += 8) {
    uint64_t rows[8];
    for (int k = 0; k < 8; ++k) std::memcpy(&rows[k], planes + size_t(k) * n + i, 8);
    transpose8x8(rows);
    for (int j = 0; j < 8; ++j) values[i + j] = std::bit_cast<double>(rows[j]);
  }
  return whole;
}

/// Appends `values` (as their little-endian bytes) plane by plane: all bytes 0, then all 1s...
template <typename U>
void put_shuffled(std::string& out, const std::vector<U>& values) {
  const size_t n = values.size();
  const size_t start = out.size();
  out.resize(start + n * sizeof(U));
  char* planes = out.data() + start;
  for (size_t i = 0; i < n; ++i) {
    for (size_t k = 0; k < sizeof(U); ++k) planes[k * n + i] = char(uint8_t(values[i] >> (8 * k)));
  }
}

template <typename U>
void get_shuffled(Reader& in, std::vector<U>& values) {
  const size_t n = values.size();
  const uint8_t* planes = in.take(n * sizeof(U));
  for (size_t i = 0; i < n; ++i) {
    U bits = 0;
    for (size_t k = 0; k < sizeof(U); ++k) bits |= U(planes[k * n + i]) << (8 * k);
    values[i] = bits;
  }
}

void put_shuffled_doubles(std::string& out, const std::vector<double>& values) {
  const size_t n = values.size();
  const size_t start = out.size();
  out.resize(start + n * sizeof(uint64_t));
  char* planes = out.data() + start;
  for (size_t i = put_planes8(planes, n, values.data()); i < n; ++i) {
    const uint64_t bits = std::bit_cast<uint64_t>(values[i]);
    for (size_t k = 0; k < sizeof(uint64_t); ++k) planes[k * n + i] = char(uint8_t(bits >> (8 * k)));
  }
}

void get_shuffled_doubles(Reader& in, std::vector<double>& values) {
  // Straight into the doubles: no temporary array of bits (the server decodes every upload).
  const size_t n = values.size();
  const uint8_t* planes = in.take(n * sizeof(uint64_t));
  for (size_t i = get_planes8(planes, n, values.data()); i < n; ++i) {
    uint64_t bits = 0;
    for (size_t k = 0; k < sizeof(uint64_t); ++k) bits |= uint64_t(planes[k * n + i]) << (8 * k);
    values[i] = std::bit_cast<double>(bits);
  }
}

// ---- header ----

struct Header {
  TileRect rect;
  uint64_t rgb_length = 0, lum2_length = 0, count_length = 0;
  uint32_t dropped_count = 0;
};

/// The sizing fields, bytes [7, 51) of the header; written twice (see the layout above).
std::string sizing_bytes(const Header& h) {
  std::string out;
  put_le<int32_t>(out, h.rect.x0);
  put_le<int32_t>(out, h.rect.y0);
  put_le<int32_t>(out, h.rect.x1);
  put_le<int32_t>(out, h.rect.y1);
  put_le<uint64_t>(out, h.rgb_length);
  put_le<uint64_t>(out, h.lum2_length);
  put_le<uint64_t>(out, h.count_length);
  put_le<uint32_t>(out, h.dropped_count);
  return out;
}

Header read_header(Reader& in) {
  const uint8_t* magic = in.take(kMagic.size());
  if (std::memcmp(magic, kMagic.data(), kMagic.size()) != 0) {
    throw CodecError("accumulation codec: not an accumulation (wrong magic)");
  }
  const uint16_t version = in.get<uint16_t>();
  if (version != kVersion) {
    throw CodecError("accumulation codec: unknown format version " + std::to_string(version) +
                     " (this build reads version " + std::to_string(kVersion) + ")");
  }
  Header h;
  h.rect.x0 = in.get<int32_t>();
  h.rect.y0 = in.get<int32_t>();
  h.rect.x1 = in.get<int32_t>();
  h.rect.y1 = in.get<int32_t>();
  h.rgb_length = in.get<uint64_t>();
  h.lum2_length = in.get<uint64_t>();
  h.count_length = in.get<uint64_t>();
  h.dropped_count = in.get<uint32_t>();
  return h;
}

/// The rectangle's pixel count, or CodecError if it is inverted, overflows int, or is larger
/// than `max_pixels`. Computed in int64 so hostile corners cannot overflow.
uint64_t checked_pixels(const TileRect& r, int64_t max_pixels) {
  const int64_t w = int64_t(r.x1) - r.x0;
  const int64_t h = int64_t(r.y1) - r.y0;
  if (w < 0 || h < 0) {
    throw CodecError("accumulation codec: rectangle has negative size " + std::to_string(w) + "x" +
                     std::to_string(h));
  }
  if (w > std::numeric_limits<int>::max() || h > std::numeric_limits<int>::max()) {
    throw CodecError("accumulation codec: rectangle is wider or taller than an int");
  }
  const int64_t pixels = w * h;  // < 2^62: no overflow
  if (pixels > max_pixels) {
    throw CodecError("accumulation codec: rectangle " + std::to_string(w) + "x" +
                     std::to_string(h) + " has more pixels than the limit of " +
                     std::to_string(max_pixels));
  }
  return uint64_t(pixels);
}

/// Checks the header's sizes against each other; returns the payload's exact size in bytes.
size_t checked_payload_size(const Header& h, int64_t max_pixels) {
  const uint64_t pixels = checked_pixels(h.rect, max_pixels);
  if (h.rgb_length != 3 * pixels || h.lum2_length != pixels || h.count_length != pixels) {
    throw CodecError("accumulation codec: array lengths (rgb " + std::to_string(h.rgb_length) +
                     ", lum2 " + std::to_string(h.lum2_length) + ", count " +
                     std::to_string(h.count_length) + ") do not match the rectangle's " +
                     std::to_string(pixels) + " pixels");
  }
  if (h.dropped_count > Accumulation::kMaxDroppedExamples) {
    throw CodecError("accumulation codec: " + std::to_string(h.dropped_count) +
                     " dropped examples, more than the maximum of " +
                     std::to_string(Accumulation::kMaxDroppedExamples));
  }
  const uint64_t fixed = kSizingSize + 16 + uint64_t(h.dropped_count) * kDroppedExampleSize;
  if (pixels > (std::numeric_limits<size_t>::max() - fixed) / kBytesPerPixel) {
    throw CodecError("accumulation codec: rectangle too large for this machine");
  }
  return size_t(fixed + pixels * kBytesPerPixel);
}

void check_encodable(const Accumulation& acc) {
  const int64_t w = int64_t(acc.rect.x1) - acc.rect.x0;
  const int64_t h = int64_t(acc.rect.y1) - acc.rect.y0;
  if (w < 0 || h < 0) throw CodecError("accumulation codec: cannot encode an inverted rectangle");
  const uint64_t pixels = uint64_t(w) * uint64_t(h);
  if (acc.rgb.size() != 3 * pixels || acc.lum2.size() != pixels || acc.count.size() != pixels) {
    throw CodecError("accumulation codec: cannot encode: array lengths (rgb " +
                     std::to_string(acc.rgb.size()) + ", lum2 " + std::to_string(acc.lum2.size()) +
                     ", count " + std::to_string(acc.count.size()) +
                     ") do not match the rectangle's " + std::to_string(pixels) + " pixels");
  }
  if (acc.dropped_examples.size() > Accumulation::kMaxDroppedExamples) {
    throw CodecError("accumulation codec: cannot encode more than " +
                     std::to_string(Accumulation::kMaxDroppedExamples) + " dropped examples");
  }
}

// ---- zstd ----

struct ZstdCCtxFree {
  void operator()(ZSTD_CCtx* c) const { ZSTD_freeCCtx(c); }
};
struct ZstdDCtxFree {
  void operator()(ZSTD_DCtx* d) const { ZSTD_freeDCtx(d); }
};

std::string compress(const std::string& payload, int level, ZSTD_CCtx* cctx) {
  auto check = [](size_t rc) {
    if (ZSTD_isError(rc)) {
      throw CodecError(std::string("accumulation codec: zstd: ") + ZSTD_getErrorName(rc));
    }
  };
  // Parameters reset each time: a call's bytes do not depend on the one before it.
  check(ZSTD_CCtx_reset(cctx, ZSTD_reset_session_and_parameters));
  check(ZSTD_CCtx_setParameter(cctx, ZSTD_c_compressionLevel, level));
  check(ZSTD_CCtx_setParameter(cctx, ZSTD_c_checksumFlag, 1));
  check(ZSTD_CCtx_setParameter(cctx, ZSTD_c_contentSizeFlag, 1));
  std::string frame(ZSTD_compressBound(payload.size()), '\0');
  const size_t size =
      ZSTD_compress2(cctx, frame.data(), frame.size(), payload.data(), payload.size());
  check(size);
  frame.resize(size);
  return frame;
}

/// Decompresses the single frame `frame` into exactly `expected` bytes of `payload` (resized;
/// its capacity is reused), checking the frame's declared size before allocating and its
/// checksum after.
void decompress(const uint8_t* frame, size_t frame_size, size_t expected,
                std::vector<uint8_t>& payload) {
  const size_t compressed = ZSTD_findFrameCompressedSize(frame, frame_size);
  if (ZSTD_isError(compressed)) {
    throw CodecError(std::string("accumulation codec: truncated or corrupt payload frame (") +
                     ZSTD_getErrorName(compressed) + ")");
  }
  if (compressed != frame_size) {
    throw CodecError("accumulation codec: " + std::to_string(frame_size - compressed) +
                     " unexpected bytes after the payload");
  }
  const unsigned long long declared = ZSTD_getFrameContentSize(frame, frame_size);
  if (declared == ZSTD_CONTENTSIZE_ERROR || declared == ZSTD_CONTENTSIZE_UNKNOWN) {
    throw CodecError("accumulation codec: payload frame does not declare its size");
  }
  if (declared != expected) {
    throw CodecError("accumulation codec: payload holds " + std::to_string(declared) +
                     " bytes, the header implies " + std::to_string(expected));
  }
  // One decompression context per thread, reused (each frame starts it afresh): creating one
  // per result allocated and initialised about 100 KB on every upload the server decoded.
  thread_local const std::unique_ptr<ZSTD_DCtx, ZstdDCtxFree> dctx(ZSTD_createDCtx());
  if (!dctx) throw CodecError("accumulation codec: cannot create a zstd context");
  payload.resize(expected);
  const size_t size =
      ZSTD_decompressDCtx(dctx.get(), payload.data(), payload.size(), frame, frame_size);
  if (ZSTD_isError(size)) {
    throw CodecError(std::string("accumulation codec: corrupt payload (") +
                     ZSTD_getErrorName(size) + ")");
  }
  if (size != expected) {
    throw CodecError("accumulation codec: payload decompressed to " + std::to_string(size) +
                     " bytes, expected " + std::to_string(expected));
  }
}

}  // namespace

struct AccumulationEncoder::Context {
  std::unique_ptr<ZSTD_CCtx, ZstdCCtxFree> cctx{ZSTD_createCCtx()};
};

AccumulationEncoder::AccumulationEncoder() : context_(std::make_unique<Context>()) {
  if (!context_->cctx) throw CodecError("accumulation codec: cannot create a zstd context");
}

AccumulationEncoder::~AccumulationEncoder() = default;

std::string encode_accumulation(const Accumulation& acc, CodecEffort effort) {
  thread_local AccumulationEncoder encoder;
  return encoder.encode(acc, effort);
}

std::string AccumulationEncoder::encode(const Accumulation& acc, CodecEffort effort) {
  check_encodable(acc);
  Header h;
  h.rect = acc.rect;
  h.rgb_length = acc.rgb.size();
  h.lum2_length = acc.lum2.size();
  h.count_length = acc.count.size();
  h.dropped_count = uint32_t(acc.dropped_examples.size());
  const std::string sizing = sizing_bytes(h);

  std::string payload = sizing;
  payload.reserve(kSizingSize + 16 + h.dropped_count * kDroppedExampleSize +
                  acc.count.size() * kBytesPerPixel);
  put_le<uint64_t>(payload, acc.nan_dropped);
  put_le<uint64_t>(payload, acc.inf_dropped);
  for (const DroppedSample& d : acc.dropped_examples) {
    put_le<int32_t>(payload, d.x);
    put_le<int32_t>(payload, d.y);
    put_le<uint32_t>(payload, d.sample_index);
  }
  put_shuffled_doubles(payload, acc.rgb);
  put_shuffled_doubles(payload, acc.lum2);
  put_shuffled(payload, acc.count);

  std::string out(kMagic.begin(), kMagic.end());
  put_le<uint16_t>(out, kVersion);
  out += sizing;
  out += compress(payload, effort == CodecEffort::fast ? kZstdLevelFast : kZstdLevelStandard,
                  context_->cctx.get());
  return out;
}

Accumulation decode_accumulation(std::string_view bytes, int64_t max_pixels) {
  const auto* data = reinterpret_cast<const uint8_t*>(bytes.data());
  Reader header_in(data, bytes.size(), "header");
  const Header h = read_header(header_in);
  const size_t payload_size = checked_payload_size(h, max_pixels);
  // The payload buffer is the thread's, reused from one decode to the next; one grown past
  // kKeptPayloadBytes (a huge tile) is given back when this decode ends, however it ends.
  static constexpr size_t kKeptPayloadBytes = size_t(16) << 20;
  thread_local std::vector<uint8_t> payload;
  struct Trim {
    ~Trim() {
      if (payload.capacity() > kKeptPayloadBytes) std::vector<uint8_t>().swap(payload);
    }
  } trim;
  decompress(data + kHeaderSize, bytes.size() - kHeaderSize, payload_size, payload);

  Reader in(payload.data(), payload.size(), "payload");
  if (std::memcmp(in.take(kSizingSize), data + kSizingOffset, kSizingSize) != 0) {
    throw CodecError("accumulation codec: header does not match the checksummed payload");
  }
  Accumulation acc;
  acc.rect = h.rect;
  acc.nan_dropped = in.get<uint64_t>();
  acc.inf_dropped = in.get<uint64_t>();
  acc.dropped_examples.resize(h.dropped_count);
  for (DroppedSample& d : acc.dropped_examples) {
    d.x = in.get<int32_t>();
    d.y = in.get<int32_t>();
    d.sample_index = in.get<uint32_t>();
  }
  acc.rgb.resize(h.rgb_length);
  acc.lum2.resize(h.lum2_length);
  acc.count.resize(h.count_length);
  get_shuffled_doubles(in, acc.rgb);
  get_shuffled_doubles(in, acc.lum2);
  get_shuffled(in, acc.count);
  if (in.left() != 0) throw CodecError("accumulation codec: payload longer than its fields");
  return acc;
}

}  // namespace tessera
