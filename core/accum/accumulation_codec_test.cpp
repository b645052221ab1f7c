#include "accum/accumulation_codec.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <string>

#include <zstd.h>

namespace tessera {
namespace {

/// Bitwise equality: operator== would call -0.0 equal to 0.0 and NaN unequal to itself.
void expect_bit_identical(const Accumulation& a, const Accumulation& b) {
  EXPECT_EQ(a.rect, b.rect);
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  ASSERT_EQ(a.lum2.size(), b.lum2.size());
  for (size_t i = 0; i < a.rgb.size(); ++i) {
    EXPECT_EQ(std::bit_cast<uint64_t>(a.rgb[i]), std::bit_cast<uint64_t>(b.rgb[i])) << "rgb " << i;
  }
  for (size_t i = 0; i < a.lum2.size(); ++i) {
    EXPECT_EQ(std::bit_cast<uint64_t>(a.lum2[i]), std::bit_cast<uint64_t>(b.lum2[i]))
        << "lum2 " << i;
  }
  EXPECT_EQ(a.count, b.count);
  EXPECT_EQ(a.nan_dropped, b.nan_dropped);
  EXPECT_EQ(a.inf_dropped, b.inf_dropped);
  EXPECT_EQ(a.dropped_examples, b.dropped_examples);
}

/// A small accumulation with edge values in every field.
Accumulation edge_case_accumulation() {
  Accumulation acc(TileRect{-3, 5, 1, 8});  // 4x3, negative corner
  const double edges[] = {0.0,
                          -0.0,
                          1e300,
                          -1e300,
                          std::numeric_limits<double>::max(),
                          std::numeric_limits<double>::lowest(),
                          std::numeric_limits<double>::min(),         // smallest normal
                          std::numeric_limits<double>::denorm_min(),  // smallest denormal
                          -std::numeric_limits<double>::denorm_min(),
                          2.2250738585072009e-308,  // largest denormal
                          1.0 / 3.0,
                          std::nextafter(1.0, 2.0)};
  for (size_t i = 0; i < acc.rgb.size(); ++i) acc.rgb[i] = edges[i % std::size(edges)];
  for (size_t i = 0; i < acc.lum2.size(); ++i) acc.lum2[i] = edges[(i * 5 + 3) % std::size(edges)];
  for (size_t i = 0; i < acc.count.size(); ++i) acc.count[i] = uint32_t(i * 2654435761u);
  acc.count[0] = std::numeric_limits<uint32_t>::max();
  acc.count[1] = 0;
  acc.nan_dropped = std::numeric_limits<uint64_t>::max();
  acc.inf_dropped = 0x0123456789abcdefull;
  acc.dropped_examples = {{-3, 5, 0}, {0, 7, std::numeric_limits<uint32_t>::max()}, {1, 6, 42}};
  return acc;
}

/// Per-pixel sums of `spp` float radiance samples, as a worker produces them: exponential
/// noise around a per-pixel level, some samples black (paths that found no light).
Accumulation noisy_accumulation(int spp, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Accumulation acc(TileRect{128, 64, 192, 128});
  for (size_t p = 0; p < acc.pixels(); ++p) {
    const double level = 0.05 + 0.5 * u(rng);
    for (int s = 0; s < spp; ++s) {
      float r = 0, g = 0, b = 0;
      if (u(rng) >= 0.3) {
        const double e = -std::log(1.0 - u(rng));
        r = float(level * e * 0.8);
        g = float(level * e * 0.6 * (0.5 + u(rng)));
        b = float(level * e * 0.4 * u(rng));
      }
      acc.rgb[3 * p] += r;
      acc.rgb[3 * p + 1] += g;
      acc.rgb[3 * p + 2] += b;
      const double y = luminance(r, g, b);
      acc.lum2[p] += y * y;
      acc.count[p] += 1;
    }
  }
  return acc;
}

Accumulation small_accumulation() {
  Accumulation acc(TileRect{0, 0, 2, 2});
  for (size_t i = 0; i < acc.rgb.size(); ++i) acc.rgb[i] = 0.25 * double(i) + 0.1;
  for (size_t i = 0; i < acc.lum2.size(); ++i) acc.lum2[i] = 0.5 * double(i) + 0.01;
  for (size_t i = 0; i < acc.count.size(); ++i) acc.count[i] = uint32_t(4 + i);
  acc.nan_dropped = 1;
  acc.dropped_examples = {{1, 1, 3}};
  return acc;
}

void put_u32(std::string& bytes, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) bytes[at + i] = char(uint8_t(v >> (8 * i)));
}
void put_u64(std::string& bytes, size_t at, uint64_t v) {
  for (int i = 0; i < 8; ++i) bytes[at + i] = char(uint8_t(v >> (8 * i)));
}

// Header offsets of format version 1 (see accumulation_codec.cpp).
constexpr size_t kVersionAt = 5, kRectAt = 7, kRgbLengthAt = 23, kLum2LengthAt = 31,
                 kCountLengthAt = 39, kDroppedAt = 47, kHeaderSize = 51;

TEST(AccumulationCodecTest, RoundTripsEdgeValuesBitForBit) {
  const Accumulation acc = edge_case_accumulation();
  const Accumulation decoded = decode_accumulation(encode_accumulation(acc));
  expect_bit_identical(acc, decoded);
}

TEST(AccumulationCodecTest, RoundTripsArbitraryBitPatternsIncludingNaNAndInf) {
  Accumulation acc(TileRect{0, 0, 7, 5});
  std::mt19937_64 rng(7);
  for (double& v : acc.rgb) v = std::bit_cast<double>(rng());
  for (double& v : acc.lum2) v = std::bit_cast<double>(rng());
  acc.rgb[0] = std::numeric_limits<double>::quiet_NaN();
  acc.rgb[1] = -std::numeric_limits<double>::infinity();
  acc.lum2[0] = std::bit_cast<double>(0x7ff0000000000001ull);  // signalling NaN payload
  const Accumulation decoded = decode_accumulation(encode_accumulation(acc));
  expect_bit_identical(acc, decoded);
}

TEST(AccumulationCodecTest, RoundTripsNoisyTileAndEmptyRect) {
  const Accumulation noisy = noisy_accumulation(16, 1);
  expect_bit_identical(noisy, decode_accumulation(encode_accumulation(noisy)));
  const Accumulation empty(TileRect{10, 10, 10, 20});
  expect_bit_identical(empty, decode_accumulation(encode_accumulation(empty)));
  const Accumulation full_examples = [] {
    Accumulation a(TileRect{0, 0, 1, 1});
    a.dropped_examples.assign(Accumulation::kMaxDroppedExamples, DroppedSample{0, 0, 9});
    return a;
  }();
  expect_bit_identical(full_examples, decode_accumulation(encode_accumulation(full_examples)));
}

TEST(AccumulationCodecTest, EncodingIsDeterministic) {
  const Accumulation acc = noisy_accumulation(4, 3);
  const std::string standard = encode_accumulation(acc);
  // The thread's zstd context is reused: a call at another level in between changes nothing.
  const std::string fast = encode_accumulation(acc, CodecEffort::fast);
  EXPECT_EQ(encode_accumulation(acc), standard);
  EXPECT_EQ(encode_accumulation(acc, CodecEffort::fast), fast);
  // An encoder of one's own (the server's merger keeps one) gives the same bytes, call after call.
  AccumulationEncoder encoder;
  EXPECT_EQ(encoder.encode(acc, CodecEffort::fast), fast);
  EXPECT_EQ(encoder.encode(acc), standard);
  EXPECT_EQ(encoder.encode(noisy_accumulation(256, 3)), encode_accumulation(noisy_accumulation(256, 3)));
  EXPECT_EQ(encoder.encode(acc, CodecEffort::fast), fast);
}

// The server's checkpoints use CodecEffort::fast: the same format, read by the same decoder, the
// same sums bit for bit, from a zstd frame of another level (which the bytes show: level -1
// leaves more of the payload uncompressed, so the frame is larger).
TEST(AccumulationCodecTest, FastEffortIsTheSameFormatAndLossless) {
  for (int spp : {1, 256}) {
    const Accumulation acc = noisy_accumulation(spp, 17);
    const std::string standard = encode_accumulation(acc);
    const std::string fast = encode_accumulation(acc, CodecEffort::fast);
    expect_bit_identical(acc, decode_accumulation(fast));
    EXPECT_EQ(fast.substr(0, kHeaderSize), standard.substr(0, kHeaderSize)) << spp;
    EXPECT_GT(fast.size(), standard.size()) << spp;
    std::printf("[ CODEC    ] 64x64 tile, %3d spp: %zu bytes at level 3, %zu at level -1\n", spp,
                standard.size(), fast.size());
  }
  expect_bit_identical(edge_case_accumulation(),
                       decode_accumulation(encode_accumulation(edge_case_accumulation(),
                                                               CodecEffort::fast)));
}

// Reports bytes per pixel for a 64x64 tile of noisy sums (36 bytes/pixel uncompressed).
// The bytes of format version 1 inside the zstd frame (header copy, counters, byte-shuffled
// planes) are fixed: an old worker's upload must decode on a new server and the reverse. The
// hashes were taken from the byte-by-byte shuffle (commit 8479b6a) before the planes were moved
// 8 values at a time (transpose8x8); the frame itself is not pinned (another zstd version may
// compress the same payload differently).
TEST(AccumulationCodecTest, ThePayloadIsFormatVersion1ByteForByte) {
  const auto payload_hash = [](const std::string& encoded) {
    constexpr size_t kHeaderSize = 51;
    const unsigned long long size =
        ZSTD_getFrameContentSize(encoded.data() + kHeaderSize, encoded.size() - kHeaderSize);
    EXPECT_EQ(size, 147516u);  // 44 + 16 + 64 x 64 x 36
    std::string payload(size_t(size), '\0');
    EXPECT_EQ(ZSTD_decompress(payload.data(), payload.size(), encoded.data() + kHeaderSize,
                              encoded.size() - kHeaderSize),
              payload.size());
    uint64_t h = 1469598103934665603ull;  // FNV-1a
    for (const unsigned char c : payload) h = (h ^ c) * 1099511628211ull;
    return h;
  };
  EXPECT_EQ(payload_hash(encode_accumulation(noisy_accumulation(1, 1))), 0x15de4e62e52ca327ull);
  EXPECT_EQ(payload_hash(encode_accumulation(noisy_accumulation(16, 1))), 0x78cf8031e81a084aull);
}

TEST(AccumulationCodecTest, CompressionRatio) {
  for (int spp : {1, 16, 256}) {
    const Accumulation acc = noisy_accumulation(spp, 11);
    const size_t bytes = encode_accumulation(acc).size();
    const double per_pixel = double(bytes) / double(acc.pixels());
    std::printf(
        "[ CODEC    ] 64x64 tile, %3d spp noisy sums: %zu bytes, %.2f bytes/pixel (raw 36)\n", spp,
        bytes, per_pixel);
    EXPECT_LT(per_pixel, 30.0);
  }
}

TEST(AccumulationCodecTest, RefusesToEncodeInconsistentAccumulation) {
  Accumulation acc(TileRect{0, 0, 2, 2});
  acc.lum2.pop_back();
  EXPECT_THROW(encode_accumulation(acc), CodecError);
  Accumulation too_many(TileRect{0, 0, 1, 1});
  too_many.dropped_examples.resize(Accumulation::kMaxDroppedExamples + 1);
  EXPECT_THROW(encode_accumulation(too_many), CodecError);
}

TEST(AccumulationCodecTest, EveryTruncationThrows) {
  const std::string bytes = encode_accumulation(small_accumulation());
  for (size_t length = 0; length < bytes.size(); ++length) {
    // A copy of exactly `length` bytes, so AddressSanitizer sees any read past the end.
    const std::string truncated = bytes.substr(0, length);
    EXPECT_THROW(decode_accumulation(truncated), CodecError) << "length " << length;
  }
}

TEST(AccumulationCodecTest, TrailingBytesThrow) {
  EXPECT_THROW(decode_accumulation(encode_accumulation(small_accumulation()) + '\0'), CodecError);
}

// Every single-bit flip, and every byte inverted: the decoder throws CodecError, or, where the
// flip hits a bit zstd ignores (an unused frame-header flag, unused entropy-table bits), the
// decoded accumulation is still bit-identical: corruption never yields a different result.
TEST(AccumulationCodecTest, EveryCorruptedByteIsDetected) {
  const Accumulation acc = small_accumulation();
  const std::string bytes = encode_accumulation(acc);
  int detected = 0, harmless = 0;
  for (size_t at = 0; at < bytes.size(); ++at) {
    for (int flip : {0x01, 0x02, 0x04, 0x08, 0x10, 0x20, 0x40, 0x80, 0xff}) {
      std::string corrupt = bytes;
      corrupt[at] = char(uint8_t(corrupt[at]) ^ flip);
      try {
        const Accumulation decoded = decode_accumulation(corrupt);
        ++harmless;
        SCOPED_TRACE("byte " + std::to_string(at) + " xor " + std::to_string(flip));
        expect_bit_identical(acc, decoded);
      } catch (const CodecError&) {
        ++detected;
      }
    }
  }
  // Nearly all flips are reported (4 of 1638 land on ignored bits with zstd 1.5.4).
  EXPECT_GT(detected, 50 * harmless);
  // Every flip in the header (magic, version, sizes) is reported.
  for (size_t at = 0; at < kHeaderSize; ++at) {
    std::string corrupt = bytes;
    corrupt[at] = char(uint8_t(corrupt[at]) ^ 0x01);
    EXPECT_THROW(decode_accumulation(corrupt), CodecError) << "header byte " << at;
  }
}

TEST(AccumulationCodecTest, WrongMagicAndVersionAreNamed) {
  std::string bytes = encode_accumulation(small_accumulation());
  std::string wrong_magic = bytes;
  wrong_magic[0] = 'X';
  try {
    decode_accumulation(wrong_magic);
    FAIL() << "no error";
  } catch (const CodecError& e) {
    EXPECT_NE(std::string(e.what()).find("magic"), std::string::npos) << e.what();
  }
  std::string new_version = bytes;
  new_version[kVersionAt] = 2;
  try {
    decode_accumulation(new_version);
    FAIL() << "no error";
  } catch (const CodecError& e) {
    EXPECT_NE(std::string(e.what()).find("version 2"), std::string::npos) << e.what();
  }
}

TEST(AccumulationCodecTest, InconsistentHeaderSizesThrow) {
  const std::string bytes = encode_accumulation(small_accumulation());
  std::string inverted = bytes;
  put_u32(inverted, kRectAt + 8, uint32_t(-5));  // x1 < x0
  EXPECT_THROW(decode_accumulation(inverted), CodecError);

  std::string rgb_length = bytes;
  put_u64(rgb_length, kRgbLengthAt, 13);
  EXPECT_THROW(decode_accumulation(rgb_length), CodecError);
  std::string lum2_length = bytes;
  put_u64(lum2_length, kLum2LengthAt, 3);
  EXPECT_THROW(decode_accumulation(lum2_length), CodecError);
  std::string count_length = bytes;
  put_u64(count_length, kCountLengthAt, ~uint64_t(0));
  EXPECT_THROW(decode_accumulation(count_length), CodecError);

  std::string dropped = bytes;
  put_u32(dropped, kDroppedAt, uint32_t(Accumulation::kMaxDroppedExamples + 1));
  try {
    decode_accumulation(dropped);
    FAIL() << "no error";
  } catch (const CodecError& e) {
    EXPECT_NE(std::string(e.what()).find("dropped"), std::string::npos) << e.what();
  }
}

/// A header claiming `rect` (with matching array lengths) in front of the small tile's frame.
std::string with_claimed_rect(TileRect rect) {
  std::string bytes = encode_accumulation(small_accumulation());
  const uint64_t pixels =
      uint64_t(int64_t(rect.x1) - rect.x0) * uint64_t(int64_t(rect.y1) - rect.y0);
  put_u32(bytes, kRectAt, uint32_t(rect.x0));
  put_u32(bytes, kRectAt + 4, uint32_t(rect.y0));
  put_u32(bytes, kRectAt + 8, uint32_t(rect.x1));
  put_u32(bytes, kRectAt + 12, uint32_t(rect.y1));
  put_u64(bytes, kRgbLengthAt, 3 * pixels);
  put_u64(bytes, kLum2LengthAt, pixels);
  put_u64(bytes, kCountLengthAt, pixels);
  return bytes;
}

TEST(AccumulationCodecTest, HugeRectThrowsWithoutAllocating) {
  constexpr int kMax = std::numeric_limits<int32_t>::max();
  constexpr int kMin = std::numeric_limits<int32_t>::min();
  // Above the default limit of 2^26 pixels: refused from the header alone.
  EXPECT_THROW(decode_accumulation(with_claimed_rect(TileRect{0, 0, 1 << 14, 1 << 13})),
               CodecError);
  // Corners that overflow an int, and about 2^62 pixels: allocating would throw bad_alloc (or
  // abort under AddressSanitizer), so a CodecError shows nothing was allocated first.
  EXPECT_THROW(decode_accumulation(with_claimed_rect(TileRect{kMin, kMin, kMax, kMax}),
                                   std::numeric_limits<int64_t>::max()),
               CodecError);
  EXPECT_THROW(decode_accumulation(with_claimed_rect(TileRect{0, 0, kMax, kMax}),
                                   std::numeric_limits<int64_t>::max()),
               CodecError);
  // Within the caller's limit (2^31 pixels, 77 GB of arrays) but the frame declares 2x2's
  // bytes: refused before the arrays are allocated.
  EXPECT_THROW(decode_accumulation(with_claimed_rect(TileRect{0, 0, 1 << 16, 1 << 15}),
                                   std::numeric_limits<int64_t>::max()),
               CodecError);
  // A caller's lower limit is honoured.
  const std::string small = encode_accumulation(small_accumulation());
  EXPECT_NO_THROW(decode_accumulation(small, 4));
  EXPECT_THROW(decode_accumulation(small, 3), CodecError);
}

}  // namespace
}  // namespace tessera
