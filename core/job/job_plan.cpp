#include "job/job_plan.h"

#include <algorithm>
#include <bit>
#include <stdexcept>
#include <string>

namespace tessera {

std::vector<TileRect> JobPlan::tiles() const {
  std::vector<TileRect> out;
  for (int y = 0; y < height; y += tile_size) {
    for (int x = 0; x < width; x += tile_size) {
      out.push_back({x, y, std::min(x + tile_size, width), std::min(y + tile_size, height)});
    }
  }
  return out;
}

int JobPlan::tile_count() const {
  return ((width + tile_size - 1) / tile_size) * ((height + tile_size - 1) / tile_size);
}

uint32_t JobPlan::batch_count() const {
  return uint32_t((uint64_t(spp) + batch_spp - 1) / batch_spp);
}

uint32_t JobPlan::batch_begin(uint32_t b) const {
  return uint32_t(std::min<uint64_t>(uint64_t(b) * batch_spp, spp));
}

uint32_t JobPlan::batch_end(uint32_t b) const {
  return uint32_t(std::min<uint64_t>(uint64_t(b + 1) * batch_spp, spp));
}

uint32_t default_batch_spp(int tile_size, int width, int height, uint32_t spp) {
  // About 2^20 samples per unit: a second or so on a typical 8-core worker for scenes like the
  // Cornell box. Tiles at the image's edge may be smaller; the full tile size sets the batch so
  // that every tile of a job shares batch boundaries.
  const int64_t tile_w = std::min(tile_size, width);
  const int64_t tile_h = std::min(tile_size, height);
  const int64_t pixels = std::max<int64_t>(1, tile_w * tile_h);
  const uint64_t target = std::max<uint64_t>(1, (uint64_t(1) << 20) / uint64_t(pixels));
  const uint64_t pow2 = std::bit_floor(target);
  return uint32_t(std::clamp<uint64_t>(pow2, 1, std::max<uint32_t>(spp, 1)));
}

JobPlan make_job_plan(int width, int height, int tile_size, uint32_t spp, uint32_t batch_spp) {
  if (width < 1 || height < 1) {
    throw std::invalid_argument("image size must be at least 1x1 (got " + std::to_string(width) +
                                "x" + std::to_string(height) + ")");
  }
  if (tile_size < 1) {
    throw std::invalid_argument("--tile: must be >= 1 (got " + std::to_string(tile_size) + ")");
  }
  if (spp < 1) throw std::invalid_argument("--spp: must be >= 1");
  JobPlan plan;
  plan.width = width;
  plan.height = height;
  plan.tile_size = tile_size;
  plan.spp = spp;
  plan.batch_spp = batch_spp == 0 ? default_batch_spp(tile_size, width, height, spp)
                                  : std::min(batch_spp, spp);
  return plan;
}

}  // namespace tessera
