// The unit of work of Tessera: render(scene, tile rectangle, sample range) -> accumulation.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "accum/accumulation.h"
#include "job/job_options.h"
#include "render/camera/pixel_filter.h"
#include "render/cancellation.h"
#include "accum/guide_tile.h"
#include "render/math/ray.h"
#include "render/sampling/sampler.h"
#include "scene/file_reader.h"
#include "scene/scene.h"
#include "wavefront/kernel_isa.h"

namespace tessera {

class TraceableScene;
class WavefrontIntegrator;

/// How Renderer::render traces a unit's paths; both give the same bits.
enum class IntegratorKind {
  /// trace_path (integrator.h): one path after another, one ray at a time.
  scalar,
  /// WavefrontIntegrator (wavefront/wavefront_integrator.h): groups of paths, one bounce at a
  /// time, their rays in Embree packets of the device's native width. The default: 5-10 %
  /// more samples per CPU-second than scalar on the benchmark scenes (BENCHMARKS.md).
  wavefront,
};

/// "scalar" or "wavefront"; throws std::invalid_argument naming `name` otherwise.
IntegratorKind integrator_kind_from_name(const std::string& name);
const char* integrator_kind_name(IntegratorKind kind);

/// Work counters of one render() call, for benchmarks and tests (not part of the result).
struct RenderStats {
  uint64_t samples = 0;      ///< camera samples (paths) traced
  uint64_t rays = 0;         ///< closest-hit queries: camera rays and bounces
  uint64_t shadow_rays = 0;  ///< occlusion queries for next-event estimation
};

/// Renders work units of one job. Built once per (scene, job options), then shared by threads:
/// render() is const and thread-safe.
///
/// Determinism: the Accumulation returned for (tile, sample range) depends only on the scene,
/// the options and those arguments; each pixel's samples are summed in sample-index order, and
/// every random number is a pure function of (seed, pixel, sample index, dimension).
class Renderer {
 public:
  /// Builds the render-ready scene (Embree BVH). Throws SceneError when the scene cannot be
  /// rendered (for example an Embree ISA the CPU lacks).
  /// `reader` serves the scene's referenced files (textures, environment maps) by bundle path.
  /// `integrator` chooses the path order (the bits are the same either way; a scene with media
  /// always renders in the scalar order, with integrators/volpath.h, and integrator() says so); `kernel` the
  /// instruction set of the wavefront order's loop (kernel_isa.h: `automatic` is
  /// TESSERA_KERNEL_ISA or the best for the CPU; the same bits on each; throws
  /// std::invalid_argument when the CPU lacks it).
  Renderer(const Scene& scene, const JobOptions& options, const FileReader& reader = {},
           IntegratorKind integrator = IntegratorKind::wavefront, KernelIsa kernel = KernelIsa::automatic);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// Renders samples [sample_begin, sample_end) of every pixel of `tile`, in parallel over the
  /// calling thread's TBB arena. `tile` must lie inside the image; sample_end > sample_begin.
  /// `stats`, when given, receives the work counters (added to what it holds).
  /// `cancel`, when given, is polled in the sample loops (cancellation.h): once it is cancelled
  /// each render thread stops within RenderCancellation::kPollSamples samples and render()
  /// throws RenderCancelled, returning nothing of the partial sums (`stats` still receives the
  /// work done). A render that is never cancelled gives the same bits with or without `cancel`.
  Accumulation render(const TileRect& tile, uint32_t sample_begin, uint32_t sample_end,
                      RenderStats* stats = nullptr,
                      const RenderCancellation* cancel = nullptr) const;

  /// The denoiser's guides of the same unit (render/guides/): each sample's camera ray, as
  /// render() draws it, followed by trace_guide; summed per pixel in sample order. Defined in
  /// render/guides/guide_render.cpp; a render that does not ask for guides never calls it.
  GuideTile render_guides(const TileRect& tile, uint32_t sample_begin, uint32_t sample_end) const;

  const JobOptions& options() const;
  /// The instruction set Embree uses, for provenance ("avx2", ...).
  std::string isa() const;
  IntegratorKind integrator() const { return integrator_; }
  /// The wavefront loop's instruction set ("avx512", ...), "-" for the scalar integrator.
  std::string kernel_isa() const;

 private:
  Accumulation render_scalar(const TileRect& tile, uint32_t sample_begin, uint32_t sample_end,
                             RenderStats* stats, const RenderCancellation* cancel) const;
  Accumulation render_wavefront(const TileRect& tile, uint32_t sample_begin, uint32_t sample_end,
                                RenderStats* stats, const RenderCancellation* cancel) const;
  /// The camera ray of sample `s` of pixel (x, y), drawn from `sampler`'s camera pairs, and in
  /// `*weight` the filter's weight of the sample (PixelFilterSampler::film_sample: 1 unless the
  /// filter has negative lobes).
  Ray camera_ray(int x, int y, PixelSampler& sampler, double* weight) const;
  /// The same, with the film pair `u_film` already drawn (the sampler's pair 0).
  Ray camera_ray(int x, int y, glm::vec2 u_film, PixelSampler& sampler, double* weight) const;

  std::unique_ptr<TraceableScene> scene_;
  std::unique_ptr<WavefrontIntegrator> wavefront_;  ///< null for IntegratorKind::scalar
  IntegratorKind integrator_;
  JobOptions options_;
  PixelFilterSampler filter_;  ///< draws each camera sample's film position (Scene::film.filter)
  /// Each thread's buffers for render_wavefront's groups (renderer.cpp), kept for the
  /// renderer's life: allocated per group they cost the Cornell box about a tenth of its render
  /// time in page faults, reallocations and the kernel's unmapping (docs/renderer.md, "The
  /// wavefront's hot path").
  struct Scratch;
  std::unique_ptr<Scratch> scratch_;
};

}  // namespace tessera
