#include "local_render.h"

#include <chrono>
#include <mutex>

#include <tbb/parallel_for.h>

namespace tessera {

LocalRenderResult render_job(const Scene& scene, const JobOptions& options,
                             const std::function<void(uint64_t)>& on_progress) {
  const auto start = std::chrono::steady_clock::now();
  LocalRenderResult result;
  result.options = options;
  const Renderer renderer(scene, options);
  result.isa = renderer.isa();
  const JobPlan plan = options.plan();
  const std::vector<TileRect> tiles = plan.tiles();
  for (const TileRect& t : tiles) result.tiles.emplace_back(t);

  uint64_t samples_done = 0;
  std::mutex progress_mutex;
  std::vector<Accumulation> batch_results(tiles.size());
  std::vector<RenderStats> batch_stats(tiles.size());
  for (uint32_t b = 0; b < plan.batch_count(); ++b) {
    const uint32_t begin = plan.batch_begin(b), end = plan.batch_end(b);
    tbb::parallel_for(size_t(0), tiles.size(), [&](size_t t) {
      batch_results[t] = renderer.render(tiles[t], begin, end, &batch_stats[t]);
      const std::lock_guard lock(progress_mutex);
      samples_done += uint64_t(tiles[t].pixel_count()) * (end - begin);
      if (on_progress) on_progress(samples_done);
    });
    for (size_t t = 0; t < tiles.size(); ++t) result.tiles[t].merge(batch_results[t]);
  }
  for (const RenderStats& s : batch_stats) {
    result.stats.samples += s.samples;
    result.stats.rays += s.rays;
    result.stats.shadow_rays += s.shadow_rays;
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace tessera
