// The path tracer: the Monte Carlo estimator of the report, with next-event estimation.
//
// One path vertex is one call of path_vertex() (path_vertex.h): both the scalar trace_path() (one
// path, one ray at a time) and the wavefront integrator (wavefront/wavefront_integrator.h: many
// paths, their rays traced in packets) call it, so a path's arithmetic and sampler calls are the
// same in both and so are its bits.
#pragma once

#include <glm/vec3.hpp>

#include "ray.h"
#include "ray_offset.h"
#include "sampler.h"
#include "traceable_scene.h"

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

/// One path between two vertices: the ray to trace next and what the vertices so far left.
/// Start a path with `PathState{camera_ray}`.
struct PathState {
  Ray ray;                    ///< the ray to trace next (unit direction)
  glm::dvec3 radiance{0.0};   ///< the estimate so far
  glm::vec3 beta{1.0f};       ///< throughput
  float eta_scale = 1.0f;     ///< undone for roulette: eta^2 of refractions, bounce mixture pdf / cosine pdf
  float prev_pdf = 0;         ///< solid-angle pdf of the BSDF sample that made `ray`
  SurfacePoint prev_sp{};     ///< where `ray` started
  int vertex = 0;             ///< the vertex `ray` will find (0 = the camera ray's hit)
  bool prev_delta = true;     ///< `ray` is the camera ray, or perfectly specular / null scattering
  /// Consecutive delta vertices the path has just scattered at (roulette spares the first few).
  int specular_run = 0;
};

/// A shadow ray a vertex asks for: when nothing blocks o + t d for t in [0, t_max]
/// (TraceableScene::occluded), `contribution` is added to the path's radiance, before the
/// next vertex is shaded.
/// Left uninitialised until a vertex fills it (it is made at every vertex of every path).
struct ShadowQuery {
  glm::vec3 o, d;
  float t_max;
  glm::dvec3 contribution;
};

/// Estimates the radiance arriving along the camera ray `ray`: path_vertex() after each
/// closest-hit query, each shadow ray traced at once. Returns the estimate in double so that
/// very bright emitters cannot overflow; NaN/Inf are left for the caller to count.
glm::dvec3 trace_path(const TraceableScene& scene, Ray ray, int max_depth, PixelSampler& sampler,
                      PathCounters& counters);

}  // namespace tessera
