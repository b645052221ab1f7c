// Renderer::render_guides (renderer.h): the guides of one unit, beside render().
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "render/guides/guide_tracer.h"
#include "render/renderer.h"
#include "render/scene/traceable_scene.h"

namespace tessera {

GuideTile Renderer::render_guides(const TileRect& tile, uint32_t sample_begin,
                                  uint32_t sample_end) const {
  if (tile.x0 < 0 || tile.y0 < 0 || tile.x1 > options_.width || tile.y1 > options_.height ||
      tile.width() <= 0 || tile.height() <= 0 || sample_end <= sample_begin) {
    throw std::invalid_argument("Renderer::render_guides: tile outside the image or no samples");
  }
  GuideTile out(tile);
  const auto trace_rows = [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y != rows.end(); ++y) {
      for (int x = tile.x0; x < tile.x1; ++x) {
        const size_t i = size_t(y - tile.y0) * size_t(tile.width()) + size_t(x - tile.x0);
        const uint64_t pixel_key = PixelSampler::pixel_key(options_.seed, x, y);
        for (uint32_t s = sample_begin; s < sample_end; ++s) {
          PixelSampler sampler(pixel_key, s);
          double weight;
          const GuideSample g = trace_guide(*scene_, camera_ray(x, y, sampler, &weight), sampler);
          for (int c = 0; c < 3; ++c) {
            out.albedo[i * 3 + size_t(c)] += g.albedo[c];
            out.normal[i * 3 + size_t(c)] += g.normal[c];
          }
          ++out.count[i];
        }
      }
    }
  };
  tbb::parallel_for(tbb::blocked_range<int>(tile.y0, tile.y1), trace_rows);
  return out;
}

}  // namespace tessera
