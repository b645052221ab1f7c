// tessera-bench-merge (merge_throughput.cpp): the results its simulated workers upload,
// encoded before the clock starts.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "accum/accumulation.h"
#include "accum/accumulation_codec.h"
#include "job/job_plan.h"
#include "merge_bench_util.h"

namespace tessera::bench_merge {

/// A plausible result of `samples` samples per pixel over `rect`: per pixel, float radiance
/// samples (a smooth image times exponential noise, a rare firefly) summed in double, their
/// squared luminance, and the count — what a worker's render gives, with the same spread of
/// mantissa bits, so the codec's compression ratio is realistic.
Accumulation noisy_accumulation(const TileRect& rect, uint32_t samples, uint64_t seed);

/// The encoded result of every (tile, samples-per-pixel) the job's units can ask for.
class ResultBank {
 public:
  explicit ResultBank(const JobPlan& plan) {
    const std::vector<TileRect> tiles = plan.tiles();
    for (uint32_t b = 0; b < plan.batch_count(); ++b) {
      const uint32_t samples = plan.batch_end(b) - plan.batch_begin(b);
      for (size_t t = 0; t < tiles.size(); ++t) {
        const auto key = std::make_pair(uint32_t(t), samples);
        if (!bytes_.contains(key)) {
          bytes_[key] =
              encode_accumulation(noisy_accumulation(tiles[t], samples, t * 7919 + samples));
        }
      }
    }
  }
  /// Throws BenchError for a unit the plan does not have.
  const std::string& get(uint32_t tile, uint32_t samples) const {
    const auto it = bytes_.find({tile, samples});
    if (it == bytes_.end()) {
      throw BenchError("no precomputed result for tile " + std::to_string(tile) + " with " +
                       std::to_string(samples) + " spp");
    }
    return it->second;
  }
  double mean_bytes() const {
    double sum = 0;
    for (const auto& [key, bytes] : bytes_) sum += double(bytes.size());
    return bytes_.empty() ? 0 : sum / double(bytes_.size());
  }

 private:
  std::map<std::pair<uint32_t, uint32_t>, std::string> bytes_;
};

}  // namespace tessera::bench_merge
