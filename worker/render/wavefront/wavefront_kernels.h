// The wavefront integrator's hot loop, compiled once per instruction set.
//
// wavefront_kernel.inc holds the loop (packets filled from the paths, traced, each lane's
// vertex shaded by path_vertex, shadow packets); wavefront_kernel_baseline.cpp,
// wavefront_kernel_avx2.cpp and wavefront_kernel_avx512.cpp each include it once, in their own
// namespace, under `#pragma GCC target` for AVX2 and AVX-512. Every header is included before
// the pragma, so the out-of-line copies of inline functions and templates they emit are
// baseline code, identical in every object (no instruction the baseline CPU lacks can reach
// the linker's pick of them); only what the compiler inlines into a kernel is built for its
// target. All three are built with -ffp-contract=off (worker/CMakeLists.txt): AVX-512F has FMA
// instructions of its own, so leaving out FMA alone would not keep GCC from fusing a multiply
// and an add there. KernelIsa (kernel_isa.h) picks one at run time.
#pragma once

#include <vector>

#include "render/integrators/integrator.h"
#include "render/sampling/sampler.h"
#include "render/scene/traceable_scene.h"
#include "render/wavefront/wavefront_integrator.h"

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define TESSERA_WAVEFRONT_X86_KERNELS 1
#else
#define TESSERA_WAVEFRONT_X86_KERNELS 0
#endif

namespace tessera {

/// What one kernel call works on: WavefrontIntegrator::trace's arguments and settings.
struct WavefrontKernelArgs {
  const TraceableScene& scene;
  int max_depth;
  int packet_width;  ///< 1, 4, 8 or 16
  std::vector<PathState>& paths;
  std::vector<PixelSampler>& samplers;
  PathCounters& counters;
  WavefrontIntegrator::Workspace& workspace;
};

using WavefrontKernel = void (*)(const WavefrontKernelArgs&);

namespace wavefront_baseline {
void trace(const WavefrontKernelArgs& args);
}
#if TESSERA_WAVEFRONT_X86_KERNELS
/// The AVX2 and AVX-512 kernels also draw Sobol pairs lane-wise (wavefront_kernel.inc's
/// SobolLanes); draw_sobol_pairs exposes that for tests: out[i] = get2d() of samplers[i] at
/// pair pairs[i] (each below PixelSampler::kSobolPairs), 16 lanes at a time.
/// They also warp the BSDF pairs they draw to cosine-weighted directions lane-wise
/// (wavefront_kernel.inc's cosine_lanes); cosine_directions exposes that for tests:
/// out[i] = square_to_cosine_hemisphere(u[i]), `width` (4, 8 or 16) lanes at a time.
namespace wavefront_avx2 {
void trace(const WavefrontKernelArgs& args);
void draw_sobol_pairs(const PixelSampler* const* samplers, const uint32_t* pairs, size_t count, glm::vec2* out);
void cosine_directions(const glm::vec2* u, size_t count, int width, glm::vec3* out);
}
namespace wavefront_avx512 {
void trace(const WavefrontKernelArgs& args);
void draw_sobol_pairs(const PixelSampler* const* samplers, const uint32_t* pairs, size_t count, glm::vec2* out);
void cosine_directions(const glm::vec2* u, size_t count, int width, glm::vec3* out);
}
#endif

}  // namespace tessera
