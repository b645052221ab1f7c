#include "job_guides.h"

#include <stdexcept>

#include "accum/guide_tile_codec.h"

namespace tessera::server {

GuideTile merge_tile_guides(int64_t job_id, uint32_t tile, const TilePosition& at,
                            const JobPlan& plan, const GuideRows& rows) {
  GuideTile merged;
  size_t next_row = 0;
  for (uint32_t b = 0; b < at.next_batch && plan.batch_begin(b) < kGuideSamples; ++b) {
    if (next_row == rows.size() || rows[next_row].first != b) {
      throw std::runtime_error("job " + std::to_string(job_id) + " tile " +
                               std::to_string(tile) + ": no guides for merged batch " +
                               std::to_string(b) + " (rendered by a worker without them?)");
    }
    merged.merge(decode_guide_tile(rows[next_row++].second, at.rect));
  }
  return merged;
}

}  // namespace tessera::server
