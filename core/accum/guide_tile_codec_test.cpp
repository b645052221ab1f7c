// The guide codec: lossless round trips, and refusals of bytes that do not fit the unit's tile.
#include "accum/guide_tile_codec.h"

#include <gtest/gtest.h>

namespace tessera {
namespace {

GuideTile sample_guide_tile(const TileRect& rect) {
  GuideTile g(rect);
  for (size_t i = 0; i < g.albedo.size(); ++i) {
    g.albedo[i] = 0.1 * double(i % 7) + 1e-17 * double(i);
    g.normal[i] = -0.5 + 0.01 * double(i % 13);
  }
  for (size_t i = 0; i < g.count.size(); ++i) g.count[i] = uint32_t(i % 5);
  return g;
}

TEST(GuideTileCodec, RoundTripsBitForBit) {
  const TileRect rect{8, 4, 21, 12};
  const GuideTile g = sample_guide_tile(rect);
  const GuideTile back = decode_guide_tile(encode_guide_tile(g, CodecEffort::fast), rect);
  EXPECT_EQ(back.rect, rect);
  EXPECT_EQ(back.albedo, g.albedo);
  EXPECT_EQ(back.normal, g.normal);
  EXPECT_EQ(back.count, g.count);
}

TEST(GuideTileCodec, RefusesAnotherTileTruncationAndGarbage) {
  const TileRect rect{0, 0, 8, 8};
  const std::string bytes = encode_guide_tile(sample_guide_tile(rect));
  EXPECT_THROW(decode_guide_tile(bytes, TileRect{0, 0, 8, 16}), CodecError);
  EXPECT_THROW(decode_guide_tile(bytes.substr(0, bytes.size() / 2), rect), CodecError);
  EXPECT_THROW(decode_guide_tile("TSACC and more", rect), CodecError);
  EXPECT_THROW(decode_guide_tile("", rect), CodecError);
}

}  // namespace
}  // namespace tessera
