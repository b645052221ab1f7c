// How a job is cut into work units: tiles x sample batches. Shared by the local renderer and the
// farm so that both produce the same units and therefore the same bits.
#pragma once

#include <cstdint>
#include <vector>

#include "accum/tile_rect.h"
#include "job/batch_schedule.h"

namespace tessera {

struct JobPlan {
  int width = 0, height = 0;
  int tile_size = 64;       ///< tiles are tile_size x tile_size, cut from the top-left
  uint32_t batch_spp = 0;   ///< samples per pixel in one work unit (progressive: the cap)
  uint32_t spp = 0;         ///< total samples per pixel
  BatchKind batch_kind = BatchKind::fixed;

  /// Tiles in row-major order.
  std::vector<TileRect> tiles() const;
  int tile_count() const;
  /// The batch schedule (batch_schedule.h): entry b is the sample range of batch b.
  BatchSchedule schedule() const { return {batch_kind, batch_spp, spp}; }
  /// Number of batches. The last batch may be short.
  uint32_t batch_count() const;
  /// Sample index range [begin, end) of batch b.
  uint32_t batch_begin(uint32_t b) const;
  uint32_t batch_end(uint32_t b) const;
};

/// The default batch size (the progressive schedule's cap), derived from the job alone (never
/// from worker speed: batch boundaries are part of the determinism contract). Aims at about a
/// million samples per unit (around a second on a typical worker), rounded down to a power of
/// two, at most spp rounded up to a power of two.
uint32_t default_batch_spp(int tile_size, int width, int height, uint32_t spp);

/// Validates and builds a plan. Throws std::invalid_argument naming the bad option.
/// batch_spp = 0 picks the progressive schedule capped at default_batch_spp; otherwise every
/// batch has min(batch_spp, spp) samples per pixel unless `kind` says progressive (a stored
/// job's schedule: batch_spp is then its cap).
JobPlan make_job_plan(int width, int height, int tile_size, uint32_t spp, uint32_t batch_spp,
                      BatchKind kind = BatchKind::fixed);

}  // namespace tessera
