// What a path carries from one vertex to the next (PathState), and the shadow ray a vertex asks
// its caller to trace (ShadowQuery): the state path_vertex() (path_vertex.h) reads and writes, the
// same in the scalar and the wavefront integrators.
#pragma once

#include <glm/vec3.hpp>

#include "render/math/ray.h"
#include "render/math/ray_offset.h"

namespace tessera {

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

}  // namespace tessera
