// The wavefront integrator: many paths advanced one vertex at a time, each bounce's rays traced
// together in Embree packets (issue 13).
#pragma once

#include <cstdint>
#include <vector>

#include "render/integrator.h"
#include "render/packet_tracer.h"
#include "render/ray.h"
#include "render/sampler.h"
#include "render/traceable_scene.h"

namespace tessera {

/// Traces a group of paths breadth-first: every live path's next ray in one packet query, then
/// each live path's vertex (path_vertex(), the scalar integrator's own), then every shadow ray
/// those vertices asked for in one occlusion query, then their contributions.
///
/// Each path gets exactly the arithmetic and sampler calls trace_path() gives it, and the
/// packet queries return the bits of TraceableScene's single-ray queries (packet_tracer.h), so
/// a path's radiance has the same bits as trace_path's whatever the packet width and whichever
/// paths share its packets. Rays and hits travel in structure-of-arrays form (RayBatch,
/// HitBatch); the per-path state (PathState) stays one record per path, since shading is scalar
/// per path. Live paths are packed in path order at each bounce, so which paths share a packet
/// depends only on the group.
///
/// Thread-safe for const use: each trace() call works in its caller's Workspace.
class WavefrontIntegrator {
 public:
  /// The buffers of one trace() call, kept by the caller between calls (one per thread) so
  /// that each group does not allocate them again. Contents are scratch.
  struct Workspace {
    RayBatch rays, shadow_rays;
    HitBatch hits;
    std::vector<uint8_t> occluded;
    std::vector<uint32_t> live, next, shadow_path;
    std::vector<glm::dvec3> shadow_contribution;
  };

  /// `scene` must outlive the integrator; `packet_width` as PacketTracer's (1, 4, 8 or 16).
  WavefrontIntegrator(const TraceableScene& scene, int max_depth, int packet_width);

  /// Traces every path of `paths` to its end: path i starts as PathState{camera ray} and uses
  /// samplers[i] (past its camera pairs, as trace_path's); its estimate ends in
  /// paths[i].radiance. `paths` and `samplers` have the same size. Adds the closest-hit and
  /// shadow rays traced to `counters`.
  void trace(std::vector<PathState>& paths, std::vector<PixelSampler>& samplers, PathCounters& counters,
             Workspace& workspace) const;

 private:
  const TraceableScene& scene_;
  int max_depth_;
  PacketTracer tracer_;
};

}  // namespace tessera
