// `tessera-worker render`: one job rendered locally through the farm's tile/batch/merge path.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "accum/accumulation.h"
#include "job/job_options.h"
#include "job/stopping_rule.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "steady_clock_source.h"

namespace tessera {

struct LocalRenderResult {
  JobOptions options;
  std::vector<Accumulation> tiles;       ///< merged, in JobPlan::tiles() order
  /// The denoiser's guides of each tile (render_job's `with_guides`; empty otherwise), merged
  /// batch by batch as `tiles` are.
  std::vector<GuideTile> guides;
  std::vector<uint32_t> tile_spp;        ///< samples per pixel merged into each tile
  std::vector<double> tile_error;        ///< each tile's estimated relative error (judge_tile)
  StopReason reason = StopReason::none;  ///< why the job stopped (max over tiles' reasons)
  /// Every render's work, a render cut by the time budget included: what was traced, which is
  /// more than the image holds (tile_spp) when the budget cut a batch.
  RenderStats stats;
  double seconds = 0;
  std::string isa;
  std::string kernel_isa;  ///< the wavefront loop's build (Renderer::kernel_isa)
};

/// Where a local render stands, as its on_progress callback sees it.
struct LocalRenderProgress {
  /// Pixel samples of the units (tile x batch) that completed: what the image holds.
  uint64_t samples_done = 0;
  /// Pixel samples traced by every render that ended, completed or cut by the time budget:
  /// the work done, whose rate is the renderer's speed.
  uint64_t samples_traced = 0;
};

/// The clock of the time rule (steady_clock_source.h).
using LocalRenderClock = SteadyClockSource;

/// Renders the job: for each batch in order, every tile still open (in parallel), then each
/// tile's result merged into that tile in batch order and judged by the job's stopping rule
/// (judge_tile) — exactly what the farm's server does, so `spp` and `noise` jobs give the farm's
/// bits. A `time` job keeps the farm's rule (docs/accuracy.md, "Time jobs"): batch 0 of every
/// tile completes and no batch starts after the budget (counted on `clock` from the call).
/// Where the farm awaits the units in flight, here once the budget passes during a later
/// batch, that batch's running renders are cancelled within
/// RenderCancellation::kPollSamples samples per thread (a time poll at each of their cancel
/// polls) and dropped, so each tile keeps the batches it completed and the image depends only on
/// which (tile, batch) units completed. `on_progress` is called after each unit ends
/// (completed or cut), from rendering threads but never concurrently. `integrator` chooses the
/// renderer's path order and `kernel` the instruction set of its wavefront loop (the same bits
/// either way). `cancel`, when given and cancelled, stops the render within
/// RenderCancellation::kPollSamples samples per thread and throws RenderCancelled
/// (cancellation.h); nothing rendered is returned. `with_guides` also renders the denoiser's
/// guides of each unit's samples below kGuideSamples (Renderer::render_guides) into `guides`;
/// the colour is the same either way.
LocalRenderResult render_job(
    const Scene& scene, const JobOptions& options,
    const std::function<void(const LocalRenderProgress&)>& on_progress = {},
    IntegratorKind integrator = IntegratorKind::wavefront, KernelIsa kernel = KernelIsa::automatic,
    const RenderCancellation* cancel = nullptr, const LocalRenderClock& clock = {},
    bool with_guides = false);

}  // namespace tessera
