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

uint32_t JobPlan::batch_count() const { return schedule().count(); }

uint32_t JobPlan::batch_begin(uint32_t b) const { return schedule().begin(b); }

uint32_t JobPlan::batch_end(uint32_t b) const { return schedule().end(b); }

uint32_t default_batch_spp(int tile_size, int width, int height, uint32_t spp) {
  // About 2^20 samples per unit: a second or so on a typical 8-core worker for scenes like the
  // Cornell box. Tiles at the image's edge may be smaller; the full tile size sets the batch so
  // that every tile of a job shares batch boundaries.
  const int64_t tile_w = std::min(tile_size, width);
  const int64_t tile_h = std::min(tile_size, height);
  const int64_t pixels = std::max<int64_t>(1, tile_w * tile_h);
  const uint64_t target = std::max<uint64_t>(1, (uint64_t(1) << 20) / uint64_t(pixels));
  const uint64_t pow2 = std::bit_floor(target);
  const uint64_t spp_pow2 = std::bit_ceil(uint64_t(std::max<uint32_t>(spp, 1)));
  return uint32_t(std::clamp<uint64_t>(pow2, 1, spp_pow2));
}

JobPlan make_job_plan(int width, int height, int tile_size, uint32_t spp, uint32_t batch_spp,
                      BatchKind kind) {
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
  if (batch_spp == 0) {
    plan.batch_kind = BatchKind::progressive;
    plan.batch_spp = default_batch_spp(tile_size, width, height, spp);
  } else if (kind == BatchKind::progressive) {
    if (!std::has_single_bit(batch_spp)) {
      throw std::invalid_argument("progressive batch cap must be a power of two (got " +
                                  std::to_string(batch_spp) + ")");
    }
    plan.batch_kind = BatchKind::progressive;
    plan.batch_spp = batch_spp;
  } else {
    plan.batch_spp = std::min(batch_spp, spp);
  }
  return plan;
}

}  // namespace tessera
