#include "accum/guide_tile.h"

#include <stdexcept>

namespace tessera {

GuideTile::GuideTile(const TileRect& r)
    : rect(r),
      albedo(size_t(r.pixel_count()) * 3, 0.0),
      normal(size_t(r.pixel_count()) * 3, 0.0),
      count(size_t(r.pixel_count()), 0) {}

void GuideTile::merge(const GuideTile& other) {
  if (count.empty()) {
    *this = other;
    return;
  }
  if (!(other.rect == rect)) throw std::invalid_argument("GuideTile::merge: another tile");
  for (size_t i = 0; i < albedo.size(); ++i) albedo[i] += other.albedo[i];
  for (size_t i = 0; i < normal.size(); ++i) normal[i] += other.normal[i];
  for (size_t i = 0; i < count.size(); ++i) count[i] += other.count[i];
}

GuideImages resolve_guides(int width, int height, const std::vector<GuideTile>& tiles) {
  const size_t values = size_t(width) * size_t(height) * 3;
  GuideImages out{{width, height, std::vector<float>(values, 0.0f)},
                  {width, height, std::vector<float>(values, 0.0f)}};
  for (const GuideTile& t : tiles) {
    for (int y = t.rect.y0; y < t.rect.y1; ++y) {
      for (int x = t.rect.x0; x < t.rect.x1; ++x) {
        const size_t i = size_t(y - t.rect.y0) * size_t(t.rect.width()) + size_t(x - t.rect.x0);
        if (t.count.empty() || t.count[i] == 0) continue;
        const size_t o = (size_t(y) * size_t(width) + size_t(x)) * 3;
        for (int c = 0; c < 3; ++c) {
          out.albedo.rgb[o + c] = float(t.albedo[i * 3 + c] / t.count[i]);
          out.normal.rgb[o + c] = float(t.normal[i * 3 + c] / t.count[i]);
        }
      }
    }
  }
  return out;
}

std::vector<ExtraChannel> guide_channels(const GuideImages& guides) {
  const char* const names[6] = {"albedo.R", "albedo.G", "albedo.B", "N.X", "N.Y", "N.Z"};
  std::vector<ExtraChannel> channels;
  const size_t pixels = guides.albedo.rgb.size() / 3;
  for (int k = 0; k < 6; ++k) {
    const std::vector<float>& from = k < 3 ? guides.albedo.rgb : guides.normal.rgb;
    ExtraChannel channel{names[k], std::vector<float>(pixels)};
    for (size_t p = 0; p < pixels; ++p) channel.values[p] = from[p * 3 + size_t(k % 3)];
    channels.push_back(std::move(channel));
  }
  return channels;
}

}  // namespace tessera
