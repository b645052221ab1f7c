// Rendering one leased unit: all of the worker's cores (its TBB arena) on the unit, while a
// watchdog thread heartbeats the lease and cancels the render when the lease is gone (expired,
// job cancelled) or a second stop signal asks to abandon the unit. The render polls the
// cancellation inside its sample loops (render/cancellation.h), so even one pixel's whole batch
// stops within a few thousand samples.
#pragma once

#include <tbb/task_arena.h>

#include <chrono>
#include <cstdint>
#include <functional>

#include "accum/accumulation.h"
#include "render/renderer.h"
#include "stop_signal.h"

namespace tessera::farm {

enum class LeaseCheck { valid, gone, unreachable };

enum class UnitOutcome {
  rendered,    ///< `result` holds the unit's accumulation
  lease_lost,  ///< the server said the lease is gone: drop the unit
  abandoned    ///< a second stop signal: hand the unit back
};

struct UnitRenderResult {
  UnitOutcome outcome = UnitOutcome::rendered;
  /// The unit's accumulation when `rendered`; empty otherwise (a cancelled render's partial
  /// sums are never returned, so they cannot be uploaded).
  Accumulation result;
  std::chrono::milliseconds elapsed{0};
  RenderStats stats;  ///< the work done, also when cancelled
};

/// Renders samples [sample_begin, sample_end) of `tile` in `arena`. `heartbeat()` is called
/// every `heartbeat_interval` from the watchdog thread; when it returns LeaseCheck::gone the
/// render is cancelled (RenderCancellation, polled in the sample loop) and lease_lost returned;
/// when `stop` counts a second signal, likewise abandoned. `unreachable` keeps rendering: the
/// lease may still be current when the server is back. Exceptions of the renderer other than
/// the cancellation's go on up.
UnitRenderResult render_unit(const Renderer& renderer, tbb::task_arena& arena, const TileRect& tile,
                             uint32_t sample_begin, uint32_t sample_end,
                             const std::function<LeaseCheck()>& heartbeat,
                             std::chrono::milliseconds heartbeat_interval, const StopSignal& stop);

}  // namespace tessera::farm
