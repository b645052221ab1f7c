// The wavefront integrator: many paths advanced one vertex at a time, each bounce's rays traced
// together in Embree packets.
#pragma once

#include <cstdint>
#include <vector>

#include "render/integrators/integrator.h"
#include "render/math/ray.h"
#include "render/sampling/sampler.h"
#include "render/scene/traceable_scene.h"
#include "render/wavefront/kernel_isa.h"

namespace tessera {

struct WavefrontKernelArgs;  // wavefront_kernels.h

/// Traces a group of paths breadth-first: every live path's next ray in Embree packets of the
/// chosen width, each live path's vertex shaded as its packet comes back (path_vertex.h, the
/// scalar integrator's own, inlined), and the shadow rays those vertices ask for in packets of
/// the same width, each traced as soon as it is full and the last one at the end of the bounce.
///
/// Each path gets exactly the arithmetic and sampler calls trace_path() gives it, and Embree's
/// packet queries return the bits of TraceableScene's single-ray queries (packet_tracer.h), so
/// a path's radiance has the same bits as trace_path's whatever the packet width and whichever
/// paths share its packets. The packets are filled straight from the paths' rays and read back
/// lane by lane, with no batch in between (with one, the packets' bookkeeping was 9-11 % of a
/// render). Live paths are packed in path order at each bounce, so which paths share a packet
/// depends only on the group.
///
/// The loop runs in one of several builds of the same source, one per instruction set
/// (wavefront_kernels.h, kernel_isa.h), all with the same bits.
///
/// Thread-safe for const use: each trace() call works in its caller's Workspace.
class WavefrontIntegrator {
 public:
  /// The buffers of one trace() call, kept by the caller between calls (one per thread) so
  /// that each group does not allocate them again. Contents are scratch.
  struct Workspace {
    std::vector<uint32_t> live, next;  ///< the paths still going, in path order
  };

  /// `scene` must outlive the integrator; `packet_width` is 1 (TraceableScene's single-ray
  /// queries), 4, 8 or 16 (Embree's packets); throws std::invalid_argument otherwise.
  /// `kernel` picks the build of the loop (resolve_kernel_isa: `automatic` reads
  /// TESSERA_KERNEL_ISA, else takes the best for the CPU); throws std::invalid_argument when
  /// this CPU or build lacks it.
  WavefrontIntegrator(const TraceableScene& scene, int max_depth, int packet_width,
                      KernelIsa kernel = KernelIsa::automatic);

  /// Traces every path of `paths` to its end: path i starts as PathState{camera ray} and uses
  /// samplers[i] (past its camera pairs, as trace_path's); its estimate ends in
  /// paths[i].radiance. `paths` and `samplers` have the same size. Adds the closest-hit and
  /// shadow rays traced to `counters`.
  void trace(std::vector<PathState>& paths, std::vector<PixelSampler>& samplers, PathCounters& counters,
             Workspace& workspace) const;

  /// out[i] = pair `pair` of samplers[i] (PixelSampler::get2d's numbers, bit for bit), drawn
  /// for many samplers at once by the AVX2 and AVX-512 kernels (their lane-wise Sobol draw),
  /// one at a time by the baseline one. The renderer draws its camera rays' film pairs so. The
  /// samplers are not advanced. `pair` is below PixelSampler::kSobolPairs.
  void draw_pairs(const PixelSampler* samplers, uint32_t pair, size_t count, glm::vec2* out) const;

  /// The kernel trace() runs (never `automatic`).
  KernelIsa kernel_isa() const { return kernel_isa_; }

 private:
  const TraceableScene& scene_;
  int max_depth_;
  int width_;
  KernelIsa kernel_isa_;
  void (*kernel_)(const WavefrontKernelArgs&);
  /// The kernel's lane-wise Sobol draw (null for the baseline: get2d one sampler at a time).
  void (*draw_)(const PixelSampler* const*, const uint32_t*, size_t, glm::vec2*);
};

}  // namespace tessera
