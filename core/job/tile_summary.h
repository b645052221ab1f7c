// What a finished job reached, tile by tile: samples per pixel and estimated error, summarised
// (min/mean/max) for reports and spread over pixels as the EXR "spp" channel. Shared by the local
// renderer and the farm's output so both report alike.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "accum/tile_rect.h"

namespace tessera {

struct TileSummary {
  uint32_t spp_min = 0, spp_max = 0;
  double spp_mean = 0;  ///< mean over tiles (each tile counts once, whatever its size)
  double error_max = 0, error_mean = 0;  ///< estimated relative error over tiles
};

/// Summary of per-tile values (the two vectors have one entry per tile); zeros when empty.
TileSummary summarize_tiles(const std::vector<uint32_t>& tile_spp,
                            const std::vector<double>& tile_error);

/// An estimated error for a report: "0.0123", or "n/a" when no tile has 2 samples per pixel
/// (`spp_max` < 2), where the estimate has no data and is 0.
std::string error_text(double error, uint32_t spp_max);

/// Each pixel's samples per pixel (its tile's), row-major over width x height: the EXR "spp"
/// channel of `noise` and `time` jobs, whose tiles may stop at different spp.
std::vector<float> spp_channel(int width, int height, const std::vector<TileRect>& tiles,
                               const std::vector<uint32_t>& tile_spp);

}  // namespace tessera
