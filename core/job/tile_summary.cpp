#include "job/tile_summary.h"

#include <algorithm>
#include <cstdio>

namespace tessera {

TileSummary summarize_tiles(const std::vector<uint32_t>& tile_spp,
                            const std::vector<double>& tile_error) {
  TileSummary s;
  if (!tile_spp.empty()) {
    s.spp_min = *std::min_element(tile_spp.begin(), tile_spp.end());
    s.spp_max = *std::max_element(tile_spp.begin(), tile_spp.end());
    double sum = 0;
    for (uint32_t v : tile_spp) sum += v;
    s.spp_mean = sum / double(tile_spp.size());
  }
  if (!tile_error.empty()) {
    s.error_max = *std::max_element(tile_error.begin(), tile_error.end());
    double sum = 0;
    for (double v : tile_error) sum += v;
    s.error_mean = sum / double(tile_error.size());
  }
  return s;
}

std::string error_text(double error, uint32_t spp_max) {
  if (spp_max < 2) return "n/a";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4f", error);
  return buf;
}

std::vector<float> spp_channel(int width, int height, const std::vector<TileRect>& tiles,
                               const std::vector<uint32_t>& tile_spp) {
  std::vector<float> out(size_t(width) * size_t(height), 0.0f);
  for (size_t t = 0; t < tiles.size() && t < tile_spp.size(); ++t) {
    const TileRect& r = tiles[t];
    for (int y = std::max(r.y0, 0); y < std::min(r.y1, height); ++y) {
      for (int x = std::max(r.x0, 0); x < std::min(r.x1, width); ++x) {
        out[size_t(y) * size_t(width) + size_t(x)] = float(tile_spp[t]);
      }
    }
  }
  return out;
}

}  // namespace tessera
