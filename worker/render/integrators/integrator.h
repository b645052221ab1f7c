// The path tracer: the Monte Carlo estimator of the report, with next-event estimation.
//
// One path vertex is one call of path_vertex() (path_vertex.h): both the scalar trace_path() (one
// path, one ray at a time) and the wavefront integrator (wavefront/wavefront_integrator.h: many
// paths, their rays traced in packets) call it, so a path's arithmetic and sampler calls are the
// same in both and so are its bits.
#pragma once

#include <glm/vec3.hpp>

#include "render/integrators/path_state.h"
#include "render/math/ray.h"
#include "render/math/ray_offset.h"
#include "render/sampling/sampler.h"
#include "render/scene/traceable_scene.h"

namespace tessera {

struct PathCounters {
  uint64_t rays = 0;
  uint64_t shadow_rays = 0;
};

/// Dimension pairs the integrator takes before the first vertex: the film jitter's, then the
/// lens's (drawn only for a thin lens).
inline constexpr uint32_t kFilmPair = 0;
inline constexpr uint32_t kLensPair = 1;
inline constexpr uint32_t kCameraPairs = 2;

/// Estimates the radiance arriving along the camera ray `ray`: path_vertex() after each
/// closest-hit query, each shadow ray traced at once. Returns the estimate in double so that
/// very bright emitters cannot overflow; NaN/Inf are left for the caller to count.
glm::dvec3 trace_path(const TraceableScene& scene, Ray ray, int max_depth, PixelSampler& sampler,
                      PathCounters& counters);

}  // namespace tessera
