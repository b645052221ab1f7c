// The options of one job, resolved from the scene's defaults and the user's overrides. The local
// renderer (`tessera-worker render`) and the farm resolve them with the same function so that the
// same command line means the same job, and the same bits.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "job/job_plan.h"
#include "job/stopping_rule.h"
#include "scene/scene.h"

namespace tessera {

/// What a user may override; an empty optional keeps the scene's value or the default.
struct JobOverrides {
  std::optional<int64_t> spp;
  std::optional<int> width, height;
  std::optional<int> tile_size;
  std::optional<int64_t> batch_spp;
  std::optional<uint64_t> seed;  ///< any 64-bit value
  std::optional<int> max_depth;
  std::optional<std::string> isa;  ///< Embree ISA to pin ("sse2", "sse4.2", "avx", "avx2", "avx512")
  // Stopping rule: at most one of spp, time_s, noise and preset (docs/accuracy.md).
  std::optional<double> time_s;    ///< `time` rule: wall-time budget in seconds
  std::optional<double> noise;     ///< `noise` rule: target relative error per tile
  std::optional<int64_t> max_spp;  ///< cap of a `noise` or `time` job (default 4096)
  std::optional<std::string> preset;  ///< a named quality preset (stopping_rule.h)
};

struct JobOptions {
  int width = 0, height = 0;
  /// Samples per pixel of the plan: the `spp` rule's N, the cap (max_spp) of `noise` and `time`
  /// jobs. Batches cover [0, spp); a `noise` or `time` job may stop before.
  uint32_t spp = 0;
  StopRule rule = StopRule::spp;
  double time_budget_s = 0;  ///< `time` rule only, > 0
  double noise_target = 0;   ///< `noise` rule only, > 0
  int max_depth = -1;  ///< Mitsuba convention; -1 unbounded
  uint64_t seed = 0;
  int tile_size = 64;
  uint32_t batch_spp = 0;  ///< resolved: never 0; the cap of a progressive schedule
  /// Progressive unless the user fixed the batch (--batch) or the job uses the noise rule.
  BatchKind batch_kind = BatchKind::fixed;
  std::string isa;         ///< empty = Embree picks the best for the CPU

  JobPlan plan() const;
};

/// Limits on what a job may ask for (the server sets them from --max-spp, --max-image-size and
/// --max-tile).
struct JobLimits {
  int64_t max_spp = int64_t(1) << 31;
  int max_dimension = 32768;  ///< width and height
  int max_tile = 4096;
};

/// Resolves and validates. Throws std::invalid_argument with a message naming the option, e.g.
/// "--spp: must be >= 1 (got -3)", or the clashing rules ("--spp and --noise are mutually
/// exclusive: give one stopping rule"). A preset is replaced by its rule's values; a `noise`
/// job's default batch is a fixed kNoiseBatchSpp (its first check lands at kNoiseMinSpp); `spp`
/// and `time` jobs get the progressive schedule (batch_schedule.h), its cap derived from spp
/// (a `time` job's cap) by default_batch_spp. `--batch B` fixes every batch at B.
JobOptions resolve_job_options(const Scene& scene, const JobOverrides& overrides,
                               const JobLimits& limits = {});

}  // namespace tessera
