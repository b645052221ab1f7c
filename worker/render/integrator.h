// The path tracer: the Monte Carlo estimator of the report, with next-event estimation.
#pragma once

#include <glm/vec3.hpp>

#include "ray.h"
#include "sampler.h"
#include "traceable_scene.h"

namespace tessera {

struct PathCounters {
  uint64_t rays = 0;
  uint64_t shadow_rays = 0;
};

/// Estimates the radiance arriving along the camera ray `ray`.
///
/// Lambertian surfaces get next-event estimation (one emitter chosen by power, one point on it
/// by area, one shadow ray) plus a cosine-weighted bounce that does not count the emission it
/// hits; emission is counted when seen directly or after a perfect mirror or glass bounce.
/// Russian roulette from the third bounce on, survival min(max(beta * eta^2), 0.95): unbiased,
/// and a path trapped by total internal reflection still ends. `max_depth` follows Mitsuba
/// (path segments including the camera ray; -1 = unbounded). Returns the estimate in double so
/// that very bright emitters cannot overflow; NaN/Inf are left for the caller to count.
glm::dvec3 trace_path(const TraceableScene& scene, Ray ray, int max_depth, PixelSampler& sampler,
                      PathCounters& counters);

/// Dimension pairs the integrator takes before the first vertex (film jitter, lens).
inline constexpr uint32_t kCameraPairs = 2;

}  // namespace tessera
