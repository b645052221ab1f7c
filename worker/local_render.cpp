#include "local_render.h"

#include <tbb/parallel_for.h>

#include <chrono>
#include <mutex>

namespace tessera {

LocalRenderResult render_job(const Scene& scene, const JobOptions& options,
                             const std::function<void(uint64_t)>& on_progress, IntegratorKind integrator,
                             KernelIsa kernel, const RenderCancellation* cancel) {
  const auto start = std::chrono::steady_clock::now();
  LocalRenderResult result;
  result.options = options;
  const Renderer renderer(scene, options, {}, integrator, kernel);
  result.isa = renderer.isa();
  result.kernel_isa = renderer.kernel_isa();
  const JobPlan plan = options.plan();
  const std::vector<TileRect> tiles = plan.tiles();
  for (const TileRect& t : tiles) result.tiles.emplace_back(t);
  result.tile_spp.assign(tiles.size(), 0);
  result.tile_error.assign(tiles.size(), 0.0);
  std::vector<size_t> open(tiles.size());
  for (size_t t = 0; t < tiles.size(); ++t) open[t] = t;

  uint64_t samples_done = 0;
  std::mutex progress_mutex;
  std::vector<Accumulation> batch_results(tiles.size());
  std::vector<RenderStats> batch_stats(tiles.size());
  const auto budget = std::chrono::duration<double>(options.time_budget_s);
  bool over_budget = false;
  for (uint32_t b = 0; b < plan.batch_count() && !open.empty(); ++b) {
    // The time rule: batch 0 of every tile always completes (no black tile); no batch starts
    // after the budget. The farm's scheduler applies the same rule (server/scheduler.h).
    if (options.rule == StopRule::time && b > 0 &&
        std::chrono::steady_clock::now() - start >= budget) {
      over_budget = true;
      break;
    }
    const uint32_t begin = plan.batch_begin(b), end = plan.batch_end(b);
    tbb::parallel_for(size_t(0), open.size(), [&](size_t i) {
      const size_t t = open[i];
      RenderStats stats;
      batch_results[t] = renderer.render(tiles[t], begin, end, &stats, cancel);
      const std::lock_guard lock(progress_mutex);
      batch_stats[t].samples += stats.samples;
      batch_stats[t].rays += stats.rays;
      batch_stats[t].shadow_rays += stats.shadow_rays;
      samples_done += uint64_t(tiles[t].pixel_count()) * (end - begin);
      if (on_progress) on_progress(samples_done);
    });
    // Merge and judge in tile order; the verdict depends only on the merged data.
    std::vector<size_t> still_open;
    for (size_t t : open) {
      result.tiles[t].merge(batch_results[t]);
      result.tile_spp[t] = end;
      const TileVerdict v = judge_tile(options.rule, options.noise_target, result.tiles[t], b + 1,
                                       plan.batch_count(), end);
      result.tile_error[t] = v.relative_error;
      if (v.finished) {
        if (result.reason != StopReason::max_spp) result.reason = v.reason;
      } else {
        still_open.push_back(t);
      }
    }
    open = std::move(still_open);
  }
  if (over_budget) result.reason = StopReason::time_budget;
  for (const RenderStats& s : batch_stats) {
    result.stats.samples += s.samples;
    result.stats.rays += s.rays;
    result.stats.shadow_rays += s.shadow_rays;
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace tessera
