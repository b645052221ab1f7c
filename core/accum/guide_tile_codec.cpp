#include "accum/guide_tile_codec.h"

#include <array>
#include <cstdint>
#include <cstring>

namespace tessera {
namespace {

constexpr std::array<char, 5> kGuideMagic = {'T', 'S', 'G', 'D', 'E'};
constexpr size_t kGuideHeader = kGuideMagic.size() + 8;  // magic, u64 albedo part's length

/// One half of a guide tile (albedo or normal sums) as an Accumulation of its rect.
Accumulation guide_half(const GuideTile& guides, const std::vector<double>& sums) {
  Accumulation acc(guides.rect);
  acc.rgb = sums;
  acc.count = guides.count;
  return acc;
}

}  // namespace

std::string encode_guide_tile(const GuideTile& guides, CodecEffort effort) {
  const std::string albedo = encode_accumulation(guide_half(guides, guides.albedo), effort);
  const std::string normal = encode_accumulation(guide_half(guides, guides.normal), effort);
  std::string out(kGuideMagic.begin(), kGuideMagic.end());
  const uint64_t length = albedo.size();
  for (size_t i = 0; i < 8; ++i) out.push_back(char(uint8_t(length >> (8 * i))));
  return out + albedo + normal;
}

GuideTile decode_guide_tile(std::string_view bytes, const TileRect& rect) {
  if (bytes.size() < kGuideHeader ||
      std::memcmp(bytes.data(), kGuideMagic.data(), kGuideMagic.size()) != 0) {
    throw CodecError("guide codec: not a guide tile");
  }
  uint64_t length = 0;
  for (size_t i = 0; i < 8; ++i) {
    length |= uint64_t(uint8_t(bytes[kGuideMagic.size() + i])) << (8 * i);
  }
  if (length > bytes.size() - kGuideHeader) throw CodecError("guide codec: truncated albedo");
  const int64_t pixels = rect.pixel_count();
  Accumulation albedo = decode_accumulation(bytes.substr(kGuideHeader, length), pixels);
  Accumulation normal = decode_accumulation(bytes.substr(kGuideHeader + length), pixels);
  if (!(albedo.rect == rect) || !(normal.rect == rect) || albedo.count != normal.count) {
    throw CodecError("guide codec: the guides do not cover the unit's tile");
  }
  GuideTile out;
  out.rect = rect;
  out.albedo = std::move(albedo.rgb);
  out.normal = std::move(normal.rgb);
  out.count = std::move(albedo.count);
  return out;
}

}  // namespace tessera
