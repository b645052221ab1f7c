#include "renderer.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "render/integrators/caustic_photons.h"
#include "render/integrators/integrator.h"
#include "render/integrators/volpath.h"
#include "render/scene/packet_tracer.h"
#include "render/scene/traceable_scene.h"
#include "wavefront/wavefront_integrator.h"

namespace tessera {
namespace {

struct RowResult {
  PathCounters counters;
  uint64_t samples = 0;
};

/// A group of the wavefront integrator traces at most this many paths at once: enough for full
/// packets after a few bounces, few enough that their state stays in the core's L2 cache.
constexpr uint32_t kWavefrontPaths = 1024;

/// One pixel's sums over its samples, added in sample-index order.
struct PixelSum {
  double r = 0, g = 0, b = 0, l2 = 0;
  uint32_t n = 0;
};

/// The NaN/Inf samples dropped in one part of a tile, in pixel then sample order.
struct DropLog {
  std::vector<DroppedSample> examples;
  uint64_t nan = 0, inf = 0;
};

/// Adds sample `s` of pixel (x, y), of estimate `l`, to `sum`, or counts it in `dropped` when
/// it is NaN or infinite.
[[gnu::always_inline]] inline void add_sample(const glm::dvec3& l, int x, int y, uint32_t s, PixelSum& sum, DropLog& dropped) {
  const bool is_nan = std::isnan(l.x) || std::isnan(l.y) || std::isnan(l.z);
  const bool is_inf = !is_nan && (std::isinf(l.x) || std::isinf(l.y) || std::isinf(l.z));
  if (is_nan || is_inf) {
    (is_nan ? dropped.nan : dropped.inf) += 1;
    if (dropped.examples.size() < Accumulation::kMaxDroppedExamples) dropped.examples.push_back({x, y, s});
    return;
  }
  sum.r += l.x;
  sum.g += l.y;
  sum.b += l.z;
  const double lum = luminance(l.x, l.y, l.z);
  sum.l2 += lum * lum;
  ++sum.n;
}

[[gnu::always_inline]] inline void store(const PixelSum& sum, size_t i, Accumulation& acc) {
  acc.rgb[i * 3 + 0] = sum.r;
  acc.rgb[i * 3 + 1] = sum.g;
  acc.rgb[i * 3 + 2] = sum.b;
  acc.lum2[i] = sum.l2;
  acc.count[i] = sum.n;
}

/// Concatenates the parts' drop logs in part order (the tile's pixel order), so the examples
/// kept do not depend on thread scheduling.
void merge_drops(const std::vector<DropLog>& parts, Accumulation& acc) {
  for (const DropLog& part : parts) {
    acc.nan_dropped += part.nan;
    acc.inf_dropped += part.inf;
    for (const DroppedSample& d : part.examples) {
      if (acc.dropped_examples.size() < Accumulation::kMaxDroppedExamples) acc.dropped_examples.push_back(d);
    }
  }
}

void add_stats(tbb::combinable<RowResult>& work, RenderStats* stats) {
  if (!stats) return;
  work.combine_each([&](const RowResult& r) {
    stats->samples += r.samples;
    stats->rays += r.counters.rays;
    stats->shadow_rays += r.counters.shadow_rays;
  });
}

/// The scalar loop polls its RenderCancellation when a thread's sample count is a multiple of
/// kPollSamples.
constexpr uint64_t kPollMask = RenderCancellation::kPollSamples - 1;
static_assert(kWavefrontPaths <= RenderCancellation::kPollSamples,
              "the wavefront loop polls once per pass of kWavefrontPaths paths");

/// Runs `trace` (a parallel_for over the tile); when a render thread gave up on a cancellation,
/// the work counters done so far still reach `stats` before RenderCancelled goes on up.
template <typename Trace>
void run_cancellable(const Trace& trace, tbb::combinable<RowResult>& work, RenderStats* stats) {
  try {
    trace();
  } catch (const RenderCancelled&) {
    add_stats(work, stats);
    throw;
  }
}

/// One thread's buffers for render_wavefront's groups: cleared, never freed, between groups,
/// tiles and render() calls, so a group neither allocates nor touches fresh pages. A thread
/// uses its buffers only inside one parallel_for body, which waits on nothing, so TBB cannot
/// start another body on that thread while they are in use.
struct WavefrontBuffers {
  std::vector<PathState> paths;
  std::vector<PixelSampler> samplers;
  std::vector<double> weights;  // the filter's weight of each path's sample
  std::vector<PixelSum> sums;
  std::vector<glm::vec2> film_pairs;  // each path's film pair (its sampler's pair 0)
  WavefrontIntegrator::Workspace workspace;

  WavefrontBuffers() {
    paths.reserve(kWavefrontPaths);
    samplers.reserve(kWavefrontPaths);
    film_pairs.reserve(kWavefrontPaths);
    weights.reserve(kWavefrontPaths);
    workspace.live.reserve(kWavefrontPaths);
    workspace.next.reserve(kWavefrontPaths);
  }
};

}  // namespace

struct Renderer::Scratch {
  tbb::enumerable_thread_specific<WavefrontBuffers> per_thread;
};

IntegratorKind integrator_kind_from_name(const std::string& name) {
  if (name == "scalar") return IntegratorKind::scalar;
  if (name == "wavefront") return IntegratorKind::wavefront;
  throw std::invalid_argument("unknown integrator \"" + name + "\" (expected scalar or wavefront)");
}

const char* integrator_kind_name(IntegratorKind kind) {
  return kind == IntegratorKind::wavefront ? "wavefront" : "scalar";
}

Renderer::Renderer(const Scene& scene, const JobOptions& options, const FileReader& reader,
                   IntegratorKind integrator, KernelIsa kernel)
    : scene_(std::make_unique<TraceableScene>(scene, options.width, options.height, options.isa,
                                              reader)),
      integrator_(integrator),
      options_(options),
      filter_(scene.film.filter),
      scratch_(std::make_unique<Scratch>()) {
  scene_->set_caustic_guide(build_caustic_guide(*scene_));
  // A scene with media renders with the volumetric path tracer, one path at a time
  // (render_scalar): the wavefront integrator knows surfaces only.
  if (scene_->has_media()) integrator_ = IntegratorKind::scalar;
  if (integrator_ == IntegratorKind::wavefront) {
    wavefront_ = std::make_unique<WavefrontIntegrator>(*scene_, options_.max_depth,
                                                       PacketTracer::native_width(scene_->embree_device()),
                                                       kernel);
  }
}

Renderer::~Renderer() = default;

const JobOptions& Renderer::options() const { return options_; }

std::string Renderer::isa() const { return scene_->isa(); }

std::string Renderer::kernel_isa() const { return wavefront_ ? kernel_isa_name(wavefront_->kernel_isa()) : "-"; }

Ray Renderer::camera_ray(int x, int y, PixelSampler& sampler, double* weight) const {
  const glm::vec2 u_film = sampler.get2d();
  return camera_ray(x, y, u_film, sampler, weight);
}

Ray Renderer::camera_ray(int x, int y, glm::vec2 u_film, PixelSampler& sampler, double* weight) const {
  // The lens pair only where the camera has a lens: a pinhole or orthographic camera ignores
  // it, and every path vertex sets its own pair (path_vertex.h), so nothing after depends on
  // whether it was drawn (the same bits, a Sobol pair's three scrambles fewer per sample).
  const ProjectiveCamera& camera = scene_->camera();
  glm::vec2 u_lens(0.0f);
  if (camera.uses_lens()) {
    sampler.set_pair(kLensPair);
    u_lens = sampler.get2d();
  }
  const FilmSample film = filter_.film_sample(x, y, u_film);
  *weight = film.weight;
  return camera.generate_ray(film.position, u_lens);
}

Accumulation Renderer::render(const TileRect& tile, uint32_t sample_begin, uint32_t sample_end,
                              RenderStats* stats, const RenderCancellation* cancel) const {
  if (tile.x0 < 0 || tile.y0 < 0 || tile.x1 > options_.width || tile.y1 > options_.height ||
      tile.width() <= 0 || tile.height() <= 0) {
    throw std::invalid_argument("Renderer::render: tile outside the image");
  }
  if (sample_end <= sample_begin) throw std::invalid_argument("Renderer::render: empty sample range");
  if (cancel && cancel->cancelled()) throw RenderCancelled();
  return wavefront_ ? render_wavefront(tile, sample_begin, sample_end, stats, cancel)
                    : render_scalar(tile, sample_begin, sample_end, stats, cancel);
}

Accumulation Renderer::render_scalar(const TileRect& tile, uint32_t sample_begin, uint32_t sample_end,
                                     RenderStats* stats, const RenderCancellation* cancel) const {
  Accumulation acc(tile);
  std::vector<DropLog> dropped_by_row(size_t(tile.height()));
  tbb::combinable<RowResult> work;

  const TraceableScene& scene = *scene_;
  const int max_depth = options_.max_depth;
  const uint64_t seed = options_.seed;
  const bool volumetric = scene.has_media();
  const bool weighted = filter_.signed_weights();

  const auto trace_rows = [&](const tbb::blocked_range<int>& rows) {
    RowResult& local = work.local();
    for (int y = rows.begin(); y != rows.end(); ++y) {
      const size_t row = size_t(y - tile.y0);
      for (int x = tile.x0; x < tile.x1; ++x) {
        PixelSum sum;
        const uint64_t pixel_key = PixelSampler::pixel_key(seed, x, y);
        for (uint32_t s = sample_begin; s < sample_end; ++s) {
          PixelSampler sampler(pixel_key, s);
          double weight;
          const Ray ray = camera_ray(x, y, sampler, &weight);
          glm::dvec3 l = volumetric ? trace_volume_path(scene, ray, max_depth, sampler, local.counters)
                                    : trace_path(scene, ray, max_depth, sampler, local.counters);
          if (weighted) l *= weight;  // a filter's negative lobe (other filters keep their bits)
          ++local.samples;
          add_sample(l, x, y, s, sum, dropped_by_row[row]);
          // The thread's sample counter says when to poll: one test of its low bits per sample.
          if ((local.samples & kPollMask) == 0 && cancel &&
              cancel->poll(RenderCancellation::kPollSamples)) {
            throw RenderCancelled();
          }
        }
        store(sum, row * size_t(tile.width()) + size_t(x - tile.x0), acc);
      }
    }
  };
  run_cancellable(
      [&] { tbb::parallel_for(tbb::blocked_range<int>(tile.y0, tile.y1), trace_rows); }, work,
      stats);
  merge_drops(dropped_by_row, acc);
  add_stats(work, stats);
  return acc;
}

// The tile's pixels, in row-major order, are cut into groups of whole pixels, each traced by
// one task: about kWavefrontPaths paths per group, at least one pixel. A group's paths (pixel,
// then sample index) go through the wavefront integrator kWavefrontPaths at a time, and are
// summed per pixel in sample order as they come back, as render_scalar sums them. The groups
// depend only on the tile and the sample range, and no path's bits depend on its group.
Accumulation Renderer::render_wavefront(const TileRect& tile, uint32_t sample_begin,
                                        uint32_t sample_end, RenderStats* stats,
                                        const RenderCancellation* cancel) const {
  Accumulation acc(tile);
  const size_t width = size_t(tile.width());
  const size_t pixels = width * size_t(tile.height());
  const uint32_t spp = sample_end - sample_begin;
  const size_t group_pixels = std::max<size_t>(1, kWavefrontPaths / spp);
  const size_t groups = (pixels + group_pixels - 1) / group_pixels;
  std::vector<DropLog> dropped_by_group(groups);
  tbb::combinable<RowResult> work;
  const uint64_t seed = options_.seed;
  const bool weighted = filter_.signed_weights();

  const auto trace_groups = [&](const tbb::blocked_range<size_t>& range) {
    RowResult& local = work.local();
    WavefrontBuffers& buffers = scratch_->per_thread.local();
    std::vector<PathState>& paths = buffers.paths;
    std::vector<PixelSampler>& samplers = buffers.samplers;
    std::vector<double>& weights = buffers.weights;
    std::vector<PixelSum>& sums = buffers.sums;
    std::vector<glm::vec2>& film_pairs = buffers.film_pairs;
    WavefrontIntegrator::Workspace& workspace = buffers.workspace;
    for (size_t group = range.begin(); group != range.end(); ++group) {
      const size_t p0 = group * group_pixels, p1 = std::min(pixels, p0 + group_pixels);
      const size_t group_paths = (p1 - p0) * spp;
      sums.assign(p1 - p0, PixelSum{});
      for (size_t first = 0; first < group_paths; first += kWavefrontPaths) {
        const size_t last = std::min(group_paths, first + kWavefrontPaths);
        paths.clear();
        samplers.clear();
        weights.clear();
        size_t key_pixel = SIZE_MAX;
        uint64_t pixel_key = 0;
        for (size_t k = first; k < last; ++k) {
          const size_t p = p0 + k / spp;
          if (p != key_pixel) {
            key_pixel = p;
            pixel_key = PixelSampler::pixel_key(seed, tile.x0 + int(p % width), tile.y0 + int(p / width));
          }
          samplers.emplace_back(pixel_key, sample_begin + uint32_t(k % spp));
        }
        // Every path's film pair at once (the kernel's lane-wise Sobol draw: get2d's bits), then
        // its camera ray.
        film_pairs.resize(samplers.size());
        wavefront_->draw_pairs(samplers.data(), kFilmPair, samplers.size(), film_pairs.data());
        for (size_t k = first; k < last; ++k) {
          const size_t p = p0 + k / spp;
          const int x = tile.x0 + int(p % width), y = tile.y0 + int(p / width);
          double weight;
          paths.push_back(PathState{camera_ray(x, y, film_pairs[k - first], samplers[k - first], &weight)});
          weights.push_back(weight);
        }
        wavefront_->trace(paths, samplers, local.counters, workspace);
        local.samples += last - first;
        // One poll per pass of at most kWavefrontPaths (= kPollSamples) paths. The thread's
        // buffers are cleared at the start of every pass, so leaving them here is safe.
        if (cancel && cancel->poll(last - first)) throw RenderCancelled();
        for (size_t k = first; k < last; ++k) {
          const size_t p = p0 + k / spp;
          const int x = tile.x0 + int(p % width), y = tile.y0 + int(p / width);
          if (weighted) paths[k - first].radiance *= weights[k - first];  // as render_scalar
          add_sample(paths[k - first].radiance, x, y, sample_begin + uint32_t(k % spp), sums[p - p0],
                     dropped_by_group[group]);
        }
      }
      for (size_t p = p0; p < p1; ++p) store(sums[p - p0], p, acc);
    }
  };
  run_cancellable(
      [&] { tbb::parallel_for(tbb::blocked_range<size_t>(0, groups, 1), trace_groups); }, work,
      stats);
  merge_drops(dropped_by_group, acc);
  add_stats(work, stats);
  return acc;
}

}  // namespace tessera
