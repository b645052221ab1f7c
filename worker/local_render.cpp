#include "local_render.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <mutex>

namespace tessera {

namespace {

/// Merges batch `b`'s completed units into `result` in tile order and judges each tile; the
/// verdict depends only on the merged data. `open` keeps the tiles still open; a tile whose unit
/// the budget cut keeps its earlier batches and is done. Returns whether a unit was cut.
bool merge_batch(const JobOptions& options, const JobPlan& plan, uint32_t b,
                 const std::vector<Accumulation>& batch_results,
                 const std::vector<GuideTile>& batch_guides, const std::vector<char>& completed,
                 LocalRenderResult& result, std::vector<size_t>& open) {
  const uint32_t begin = plan.batch_begin(b), end = plan.batch_end(b);
  const bool with_guides = !result.guides.empty();
  std::vector<size_t> still_open;
  bool cut = false;
  for (size_t t : open) {
    if (completed[t] == 0) {
      cut = true;
      continue;
    }
    result.tiles[t].merge(batch_results[t]);
    if (with_guides && begin < kGuideSamples) result.guides[t].merge(batch_guides[t]);
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
  return cut;
}

}  // namespace

LocalRenderResult render_job(const Scene& scene, const JobOptions& options,
                             const std::function<void(const LocalRenderProgress&)>& on_progress,
                             IntegratorKind integrator, KernelIsa kernel,
                             const RenderCancellation* cancel, const LocalRenderClock& clock,
                             bool with_guides) {
  const SteadyClockSource now = or_steady_clock(clock);
  const auto start = now();
  LocalRenderResult result;
  result.options = options;
  const Renderer renderer(scene, options, {}, integrator, kernel);
  result.isa = renderer.isa();
  result.kernel_isa = renderer.kernel_isa();
  const JobPlan plan = options.plan();
  const std::vector<TileRect> tiles = plan.tiles();
  for (const TileRect& t : tiles) result.tiles.emplace_back(t);
  if (with_guides) result.guides.assign(tiles.size(), GuideTile{});
  result.tile_spp.assign(tiles.size(), 0);
  result.tile_error.assign(tiles.size(), 0.0);
  std::vector<size_t> open(tiles.size());
  for (size_t t = 0; t < tiles.size(); ++t) open[t] = t;

  LocalRenderProgress progress;
  std::mutex progress_mutex;
  std::vector<Accumulation> batch_results(tiles.size());
  std::vector<GuideTile> batch_guides(with_guides ? tiles.size() : 0);
  std::vector<char> completed(tiles.size());
  const bool timed = options.rule == StopRule::time;
  const auto deadline =
      start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                  std::chrono::duration<double>(options.time_budget_s));
  bool over_budget = false;
  for (uint32_t b = 0; b < plan.batch_count() && !open.empty(); ++b) {
    // The time rule: batch 0 of every tile always completes (no black tile); no batch starts
    // after the budget. The farm's scheduler applies the same rule (server/scheduler.h).
    if (timed && b > 0 && now() >= deadline) {
      over_budget = true;
      break;
    }
    // A later batch of a time job also stops when the budget passes while it runs, so that the
    // budget holds to a poll rather than to a batch (the farm awaits such units, bounded by
    // their lease): its renders poll a cancellation of their own, tripped by the user's cancel
    // or by the clock at any poll, so no thread traces more than one poll's samples
    // (RenderCancellation::kPollSamples) past the budget. Every other batch stops for the
    // user's cancel alone.
    const bool cut_by_time = timed && b > 0;
    RenderCancellation batch_cancel;
    if (cut_by_time) {
      batch_cancel.set_poll_hook([&](uint64_t samples) {
        if ((cancel != nullptr && cancel->poll(samples)) || now() >= deadline) {
          batch_cancel.cancel();
        }
      });
    }
    const RenderCancellation* render_cancel = cut_by_time ? &batch_cancel : cancel;
    const uint32_t begin = plan.batch_begin(b), end = plan.batch_end(b);
    std::fill(completed.begin(), completed.end(), 0);
    tbb::parallel_for(size_t(0), open.size(), [&](size_t i) {
      const size_t t = open[i];
      RenderStats stats;
      try {
        // A unit due after the budget is not begun.
        if (cut_by_time && ((cancel != nullptr && cancel->cancelled()) || now() >= deadline)) {
          batch_cancel.cancel();
        }
        batch_results[t] = renderer.render(tiles[t], begin, end, &stats, render_cancel);
        if (with_guides && begin < kGuideSamples) {
          batch_guides[t] = renderer.render_guides(tiles[t], begin, std::min(end, kGuideSamples));
        }
        completed[t] = 1;
      } catch (const RenderCancelled&) {
        // The user's cancel ends the command with nothing; the budget only drops this unit.
        if (!cut_by_time || (cancel != nullptr && cancel->cancelled())) throw;
      }
      const std::lock_guard lock(progress_mutex);
      result.stats.samples += stats.samples;
      result.stats.rays += stats.rays;
      result.stats.shadow_rays += stats.shadow_rays;
      progress.samples_traced += stats.samples;
      if (completed[t] != 0) {
        progress.samples_done += uint64_t(tiles[t].pixel_count()) * (end - begin);
      }
      if (on_progress) on_progress(progress);
    });
    const bool cut =
        merge_batch(options, plan, b, batch_results, batch_guides, completed, result, open);
    if (cut) {
      over_budget = true;
      break;
    }
  }
  if (over_budget) result.reason = StopReason::time_budget;
  result.seconds = std::chrono::duration<double>(now() - start).count();
  return result;
}

}  // namespace tessera
