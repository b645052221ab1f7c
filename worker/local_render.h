// `tessera-worker render`: one job rendered locally through the farm's tile/batch/merge path.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "accum/accumulation.h"
#include "job/job_options.h"
#include "render/renderer.h"
#include "scene/scene.h"

namespace tessera {

struct LocalRenderResult {
  JobOptions options;
  std::vector<Accumulation> tiles;  ///< merged, in JobPlan::tiles() order
  RenderStats stats;
  double seconds = 0;
  std::string isa;
};

/// Renders every unit of the job: for each batch in order, all tiles (in parallel), then each
/// tile's result merged into that tile in batch order — exactly what the farm's server does.
/// `on_progress(samples_done_total)` is called after each unit, from rendering threads but
/// never concurrently.
LocalRenderResult render_job(const Scene& scene, const JobOptions& options,
                             const std::function<void(uint64_t)>& on_progress = {});

}  // namespace tessera
