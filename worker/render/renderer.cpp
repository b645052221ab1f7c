#include "renderer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include "integrator.h"
#include "traceable_scene.h"

namespace tessera {
namespace {

struct RowResult {
  PathCounters counters;
  uint64_t samples = 0;
};

}  // namespace

Renderer::Renderer(const Scene& scene, const JobOptions& options, const FileReader& reader)
    : scene_(std::make_unique<TraceableScene>(scene, options.width, options.height, options.isa,
                                              reader)),
      options_(options),
      filter_(scene.film.filter) {}

Renderer::~Renderer() = default;

const JobOptions& Renderer::options() const { return options_; }

std::string Renderer::isa() const { return scene_->isa(); }

Accumulation Renderer::render(const TileRect& tile, uint32_t sample_begin, uint32_t sample_end,
                              RenderStats* stats) const {
  if (tile.x0 < 0 || tile.y0 < 0 || tile.x1 > options_.width || tile.y1 > options_.height ||
      tile.width() <= 0 || tile.height() <= 0) {
    throw std::invalid_argument("Renderer::render: tile outside the image");
  }
  if (sample_end <= sample_begin) throw std::invalid_argument("Renderer::render: empty sample range");

  Accumulation acc(tile);
  // Dropped samples are collected per row and concatenated in row order afterwards, so the
  // examples kept do not depend on thread scheduling.
  std::vector<std::vector<DroppedSample>> dropped_by_row(size_t(tile.height()));
  std::vector<uint64_t> nan_by_row(size_t(tile.height()), 0), inf_by_row(size_t(tile.height()), 0);
  tbb::combinable<RowResult> work;

  const TraceableScene& scene = *scene_;
  const int max_depth = options_.max_depth;
  const uint64_t seed = options_.seed;

  tbb::parallel_for(tbb::blocked_range<int>(tile.y0, tile.y1), [&](const tbb::blocked_range<int>& rows) {
    RowResult& local = work.local();
    for (int y = rows.begin(); y != rows.end(); ++y) {
      const size_t row = size_t(y - tile.y0);
      for (int x = tile.x0; x < tile.x1; ++x) {
        const size_t i = row * size_t(tile.width()) + size_t(x - tile.x0);
        double sum_r = 0, sum_g = 0, sum_b = 0, sum_l2 = 0;
        uint32_t n = 0;
        const uint64_t pixel_key = PixelSampler::pixel_key(seed, x, y);
        for (uint32_t s = sample_begin; s < sample_end; ++s) {
          PixelSampler sampler(pixel_key, s);
          const glm::vec2 u_film = sampler.get2d();
          const glm::vec2 u_lens = sampler.get2d();
          const Ray ray = scene.camera().generate_ray(filter_.film_position(x, y, u_film), u_lens);
          const glm::dvec3 l = trace_path(scene, ray, max_depth, sampler, local.counters);
          ++local.samples;
          const bool is_nan = std::isnan(l.x) || std::isnan(l.y) || std::isnan(l.z);
          const bool is_inf = !is_nan && (std::isinf(l.x) || std::isinf(l.y) || std::isinf(l.z));
          if (is_nan || is_inf) {
            (is_nan ? nan_by_row : inf_by_row)[row] += 1;
            if (dropped_by_row[row].size() < Accumulation::kMaxDroppedExamples) {
              dropped_by_row[row].push_back({x, y, s});
            }
            continue;
          }
          sum_r += l.x;
          sum_g += l.y;
          sum_b += l.z;
          const double lum = luminance(l.x, l.y, l.z);
          sum_l2 += lum * lum;
          ++n;
        }
        acc.rgb[i * 3 + 0] = sum_r;
        acc.rgb[i * 3 + 1] = sum_g;
        acc.rgb[i * 3 + 2] = sum_b;
        acc.lum2[i] = sum_l2;
        acc.count[i] = n;
      }
    }
  });

  for (size_t row = 0; row < dropped_by_row.size(); ++row) {
    acc.nan_dropped += nan_by_row[row];
    acc.inf_dropped += inf_by_row[row];
    for (const DroppedSample& d : dropped_by_row[row]) {
      if (acc.dropped_examples.size() < Accumulation::kMaxDroppedExamples) {
        acc.dropped_examples.push_back(d);
      }
    }
  }
  if (stats) {
    work.combine_each([&](const RowResult& r) {
      stats->samples += r.samples;
      stats->rays += r.counters.rays;
      stats->shadow_rays += r.counters.shadow_rays;
    });
  }
  return acc;
}

}  // namespace tessera
