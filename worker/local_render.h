// `tessera-worker render`: one job rendered locally through the farm's tile/batch/merge path.
#pragma once

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

namespace tessera {

struct LocalRenderResult {
  JobOptions options;
  std::vector<Accumulation> tiles;       ///< merged, in JobPlan::tiles() order
  std::vector<uint32_t> tile_spp;        ///< samples per pixel merged into each tile
  std::vector<double> tile_error;        ///< each tile's estimated relative error (judge_tile)
  StopReason reason = StopReason::none;  ///< why the job stopped (max over tiles' reasons)
  RenderStats stats;
  double seconds = 0;
  std::string isa;
  std::string kernel_isa;  ///< the wavefront loop's build (Renderer::kernel_isa)
};

/// Renders the job: for each batch in order, every tile still open (in parallel), then each
/// tile's result merged into that tile in batch order and judged by the job's stopping rule
/// (judge_tile) — exactly what the farm's server does, so `spp` and `noise` jobs give the farm's
/// bits. A `time` job starts no batch after its budget (steady clock) and keeps what is merged.
/// `on_progress(samples_done_total)` is called after each unit, from rendering threads but
/// never concurrently. `integrator` chooses the renderer's path order and `kernel` the
/// instruction set of its wavefront loop (the same bits either way). `cancel`, when given and
/// cancelled, stops the render within RenderCancellation::kPollSamples samples per thread and
/// throws RenderCancelled (cancellation.h); nothing rendered is returned.
LocalRenderResult render_job(const Scene& scene, const JobOptions& options,
                             const std::function<void(uint64_t)>& on_progress = {},
                             IntegratorKind integrator = IntegratorKind::wavefront,
                             KernelIsa kernel = KernelIsa::automatic,
                             const RenderCancellation* cancel = nullptr);

}  // namespace tessera
