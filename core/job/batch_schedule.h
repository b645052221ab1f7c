// A job's batch schedule: which sample indices each work unit (tile, batch b) renders. Entry b of
// the schedule is the block of sample indices [begin(b), end(b)) that batch b adds to every
// pixel of a tile. It is a pure function of the job (its spp, its batch size and the kind
// below), stored with the job, and shared by the farm and `tessera-worker render` so that both
// merge the same batches in the same order (docs/farm.md, "Batches").
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace tessera {

enum class BatchKind {
  /// Every batch has `batch_spp` samples per pixel: [b*batch_spp, (b+1)*batch_spp). The
  /// schedule of `--batch B`, of noise jobs, and of every job stored before schedules existed.
  fixed,
  /// 1, 1, 2, 4, ... samples per pixel, doubling up to the cap `batch_spp` (a power of two), then
  /// `batch_spp` each: [0,1), [1,2), [2,4), [4,8), ..., [cap, 2 cap), ... Every batch is an
  /// aligned power-of-two block of sample indices, so each is a (0,k,2)-net of the sampler and
  /// the preview of the whole image sharpens after every round of batches.
  progressive,
};

std::string_view to_string(BatchKind kind);
std::optional<BatchKind> batch_kind_from_string(std::string_view name);

/// The schedule of one job. The last batch may be short (it ends at spp).
struct BatchSchedule {
  BatchKind kind = BatchKind::fixed;
  uint32_t batch_spp = 1;  ///< fixed: every batch; progressive: the cap (a power of two)
  uint32_t spp = 1;        ///< samples per pixel in all: batches cover [0, spp)

  /// Number of batches (>= 1 when spp >= 1).
  uint32_t count() const;
  /// Sample index range [begin(b), end(b)) of batch b; both clamp to spp past the last batch.
  uint32_t begin(uint32_t b) const;
  uint32_t end(uint32_t b) const;
  /// The samples per pixel a tile holds once batches [0, merged) are merged: end(merged - 1),
  /// 0 when merged = 0.
  uint32_t spp_after(uint32_t merged) const;
};

}  // namespace tessera
