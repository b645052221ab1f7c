#include "render/wavefront/wavefront_integrator.h"

#include <algorithm>
#include <cstdlib>
#include <iterator>
#include <stdexcept>
#include <string>

#include "render/wavefront/wavefront_kernels.h"

namespace tessera {
namespace {

/// The build of the loop for `isa`, and its lane-wise Sobol draw (none in the baseline build).
struct KernelEntry {
  WavefrontKernel trace;
  void (*draw)(const PixelSampler* const*, const uint32_t*, size_t, glm::vec2*);
};

KernelEntry kernel_for(KernelIsa isa) {
  switch (isa) {
#if TESSERA_WAVEFRONT_X86_KERNELS
    case KernelIsa::avx2: return {&wavefront_avx2::trace, &wavefront_avx2::draw_sobol_pairs};
    case KernelIsa::avx512: return {&wavefront_avx512::trace, &wavefront_avx512::draw_sobol_pairs};
#endif
    default: return {&wavefront_baseline::trace, nullptr};
  }
}

}  // namespace

WavefrontIntegrator::WavefrontIntegrator(const TraceableScene& scene, int max_depth, int packet_width,
                                         KernelIsa kernel)
    : scene_(scene),
      max_depth_(max_depth),
      width_(packet_width),
      kernel_isa_(resolve_kernel_isa(kernel, std::getenv("TESSERA_KERNEL_ISA"))),
      kernel_(kernel_for(kernel_isa_).trace),
      draw_(kernel_for(kernel_isa_).draw) {
  if (width_ != 1 && width_ != 4 && width_ != 8 && width_ != 16) {
    throw std::invalid_argument("packet width " + std::to_string(width_) + " is not 1, 4, 8 or 16");
  }
}

void WavefrontIntegrator::trace(std::vector<PathState>& paths, std::vector<PixelSampler>& samplers,
                                PathCounters& counters, Workspace& workspace) const {
  if (samplers.size() != paths.size()) {
    throw std::invalid_argument("WavefrontIntegrator::trace: " + std::to_string(paths.size()) + " paths but " +
                                std::to_string(samplers.size()) + " samplers");
  }
  kernel_(WavefrontKernelArgs{scene_, max_depth_, width_, paths, samplers, counters, workspace});
}

void WavefrontIntegrator::draw_pairs(const PixelSampler* samplers, uint32_t pair, size_t count,
                                     glm::vec2* out) const {
  if (pair >= PixelSampler::kSobolPairs) {
    throw std::invalid_argument("WavefrontIntegrator::draw_pairs: pair " + std::to_string(pair) +
                                " is not a Sobol pair");
  }
  if (!draw_) {
    for (size_t i = 0; i < count; ++i) {
      PixelSampler s = samplers[i];
      s.set_pair(pair);
      out[i] = s.get2d();
    }
    return;
  }
  // The kernels take a sampler and a pair index per lane; 16 lanes at a time.
  uint32_t pairs[16];
  std::fill(std::begin(pairs), std::end(pairs), pair);
  const PixelSampler* lanes[16];
  for (size_t first = 0; first < count; first += 16) {
    const size_t n = std::min<size_t>(16, count - first);
    for (size_t l = 0; l < n; ++l) lanes[l] = &samplers[first + l];
    draw_(lanes, pairs, n, out + first);
  }
}

}  // namespace tessera
