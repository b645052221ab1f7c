// tessera-bench-rays SCENE [--seconds S] [--threads N] [--mode scalar|packet] [--widths 1,8,16]
// [--rounds 3] [--isa ISA] [--spp N] [--integrator scalar|wavefront|both]
// [--kernel-isa auto|baseline|avx2|avx512[,SECOND]]:
// Embree's raw ray throughput on a scene (the limit the renderer can approach) beside the
// renderer's own rays/s on the same scene, in the same run.
//
// Raw rays: a pool of path-like rays — from the camera through random pixels, then from each
// first hit in a cosine-distributed direction — traced with closest-hit queries in parallel,
// nothing else done per ray (TraceableScene::intersect, which also builds the surface point).
// --mode packet adds the packet tracer (worker/render/scene/packet_tracer.h) on the same pool: for each
// width, closest-hit (rtcIntersect1/4/8/16) and occlusion (rtcOccluded1/4/8/16, same rays and
// t_max) queries, packets cut in pool order, 4096-ray chunks spread over the threads; every
// query runs once per round, rounds interleaved with the scalar query, medians printed.
// The renderer: one 64x64-tile batch after another through Renderer::render, counting its
// closest-hit and shadow rays, with the integrator --integrator names (renderer.h). With
// `--integrator both`, a scalar and a wavefront renderer take turns on the same units, tile by
// tile, for --seconds each, and the process CPU time of every render() call is kept: the median
// of the per-tile ratios wavefront / scalar of CPU seconds per sample compares the two under the
// same load (on a shared machine, wall-clock rates of separate runs mostly measure the load).
// `--kernel-isa A,B` does the same with two builds of the wavefront loop (kernel_isa.h).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <ctime>
#include <functional>
#include <map>
#include <cstdio>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <tbb/global_control.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "render/math/frame.h"
#include "render/renderer.h"
#include "render/sampling/warp.h"
#include "render/scene/packet_tracer.h"
#include "render/scene/traceable_scene.h"
#include "scene/loader/scene_loader.h"

using namespace tessera;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::vector<Ray> make_rays(const TraceableScene& scene, int width, int height, size_t count) {
  std::vector<Ray> rays;
  rays.reserve(count);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  while (rays.size() < count) {
    const Ray camera = scene.camera().generate_ray({u(rng) * float(width), u(rng) * float(height)}, {0.5f, 0.5f});
    rays.push_back(camera);
    Hit hit;
    if (!scene.intersect(camera, &hit)) continue;
    glm::vec3 n = glm::dot(camera.d, hit.sp.ng) < 0 ? hit.sp.ng : -hit.sp.ng;
    SurfacePoint sp = hit.sp;
    sp.ng = n;
    const glm::vec3 w = Frame(n).to_world(square_to_cosine_hemisphere({u(rng), u(rng)}));
    rays.push_back({offset_ray_origin(sp, w), w});
  }
  return rays;
}

double thread_cpu_seconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

/// A query's throughput: rays per wall-clock second (all threads together) and rays per CPU
/// second (time the tracing threads were actually on a core: on a shared, loaded machine this
/// one measures the query, the wall rate mostly the load).
struct Rate {
  double wall = 0;
  double cpu = 0;
};

/// The rate of `trace(begin, end)` over chunks of `count` rays, the whole pool traced again
/// until `seconds` have passed; `*passes` (if given) receives how many times.
template <typename Trace>
Rate rate(size_t count, double seconds, Trace trace, uint64_t* passes = nullptr) {
  constexpr size_t chunk = 4096;  // a multiple of every packet width: packets never straddle chunks
  uint64_t traced = 0;
  std::atomic<int64_t> cpu_ns{0};
  const auto t0 = std::chrono::steady_clock::now();
  while (seconds_since(t0) < seconds) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, (count + chunk - 1) / chunk, 1),
                      [&](const tbb::blocked_range<size_t>& r) {
                        const double c0 = thread_cpu_seconds();
                        for (size_t c = r.begin(); c != r.end(); ++c) {
                          trace(c * chunk, std::min(count, (c + 1) * chunk));
                        }
                        cpu_ns += int64_t(1e9 * (thread_cpu_seconds() - c0));
                      });
    traced += count;
  }
  if (passes) *passes = traced / count;
  return {double(traced) / seconds_since(t0), double(traced) / (1e-9 * double(cpu_ns))};
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[size_t(q * double(v.size() - 1) + 0.5)];
}

/// The packet tracer at each width on `pool`, closest-hit and occlusion, interleaved with
/// `scalar` (TraceableScene::intersect's rate on the same rays) in each of `rounds` rounds, so
/// load drifts on a shared machine hit every query alike; prints every round and the medians,
/// with each width's rate divided by the same round's scalar rate. Returns the widest width's
/// median closest-hit rays per CPU-second.
double packet_rates(const TraceableScene& traceable, const std::vector<Ray>& pool,
                  const std::vector<int>& widths, double seconds, int rounds,
                  const std::function<Rate()>& scalar) {
  RayBatch rays;
  rays.resize(pool.size());
  for (size_t i = 0; i < pool.size(); ++i) rays.set(i, pool[i]);
  HitBatch hits;
  hits.resize(pool.size());
  std::vector<uint8_t> occluded(pool.size());
  std::printf("packet tracer (native width %d), same pool, %d rounds of %.1f s per query:\n",
              PacketTracer::native_width(traceable.embree_device()), rounds, seconds);
  std::vector<double> scalar_rates, scalar_wall;
  std::map<int, std::vector<double>> closest, shadow, closest_ratio, closest_wall;
  for (int round = 1; round <= rounds; ++round) {
    const Rate s = scalar();
    scalar_rates.push_back(s.cpu);
    scalar_wall.push_back(s.wall);
    std::printf("  round %d: scalar %.2f", round, s.cpu / 1e6);
    for (int width : widths) {
      const PacketTracer tracer(traceable.embree_scene(), width);
      const Rate c = rate(pool.size(), seconds, [&](size_t b, size_t e) { tracer.intersect(rays, b, e, &hits); });
      const Rate o = rate(pool.size(), seconds, [&](size_t b, size_t e) { tracer.occluded(rays, b, e, &occluded); });
      closest[width].push_back(c.cpu);
      closest_wall[width].push_back(c.wall);
      shadow[width].push_back(o.cpu);
      closest_ratio[width].push_back(c.cpu / s.cpu);
      std::printf(", width %d %.2f / %.2f", width, c.cpu / 1e6, o.cpu / 1e6);
    }
    std::printf(" M rays per CPU-second (closest-hit / occluded)\n");
  }
  size_t hit = 0, blocked = 0;
  for (size_t i = 0; i < pool.size(); ++i) {
    hit += hits.geometry[i] != RTC_INVALID_GEOMETRY_ID;
    blocked += occluded[i];
  }
  std::printf("  medians, M rays per CPU-second (wall-clock M rays/s):\n"
              "  scalar (TraceableScene::intersect): closest-hit %.2f (%.2f)\n",
              median(scalar_rates) / 1e6, median(scalar_wall) / 1e6);
  for (int width : widths) {
    std::printf("  width %2d: closest-hit %.2f (%.2f), %.2fx the scalar rate; occluded %.2f\n", width,
                median(closest[width]) / 1e6, median(closest_wall[width]) / 1e6, median(closest_ratio[width]),
                median(shadow[width]) / 1e6);
  }
  std::printf("  (%.1f %% of the pool hit, %.1f %% blocked)\n", 100.0 * double(hit) / double(pool.size()),
              100.0 * double(blocked) / double(pool.size()));
  return median(closest[*std::max_element(widths.begin(), widths.end())]);
}

double process_cpu_seconds() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

/// Two renderers alternating tile by tile on the same units (each tile rendered by both, in
/// alternating order), until each has rendered for `seconds` of wall time; prints each one's
/// samples per CPU-second (median over tiles) and the median of the per-tile ratios b / a.
/// --integrator both: a = scalar, b = wavefront; --kernel-isa A,B: the wavefront loop's
/// builds A and B.
void compare_renderers(const Renderer& a, const std::string& a_name, const Renderer& b, const std::string& b_name,
                       const char* what, const JobOptions& options, uint32_t spp, double seconds) {
  const std::vector<TileRect> tiles = options.plan().tiles();
  std::vector<double> a_rate, b_rate, ratio;
  double a_wall = 0, b_wall = 0;
  uint64_t a_samples = 0, b_samples = 0;
  const auto timed = [](const Renderer& r, const TileRect& tile, uint32_t begin, uint32_t end, double* wall,
                        uint64_t* samples) {
    RenderStats stats;
    const double c0 = process_cpu_seconds();
    const auto t0 = std::chrono::steady_clock::now();
    r.render(tile, begin, end, &stats);
    *wall += seconds_since(t0);
    *samples += stats.samples;
    return double(stats.samples) / (process_cpu_seconds() - c0);
  };
  uint32_t batch = 0;
  size_t turn = 0;
  while (a_wall < seconds || b_wall < seconds) {
    for (const TileRect& tile : tiles) {
      const uint32_t begin = batch * spp, end = (batch + 1) * spp;
      double ra, rb;
      if (turn++ % 2 == 0) {
        ra = timed(a, tile, begin, end, &a_wall, &a_samples);
        rb = timed(b, tile, begin, end, &b_wall, &b_samples);
      } else {
        rb = timed(b, tile, begin, end, &b_wall, &b_samples);
        ra = timed(a, tile, begin, end, &a_wall, &a_samples);
      }
      a_rate.push_back(ra);
      b_rate.push_back(rb);
      ratio.push_back(rb / ra);
      if (a_wall >= seconds && b_wall >= seconds) break;
    }
    ++batch;
  }
  std::printf("%s alternating on %zu tiles of %u spp: %s %.3f M samples per CPU-second (%.3f M/s "
              "wall), %s %.3f M samples per CPU-second (%.3f M/s wall) (medians over tiles); "
              "%s / %s per tile: median %.3f, quartiles %.3f-%.3f\n",
              what, ratio.size(), spp, a_name.c_str(), median(a_rate) / 1e6, double(a_samples) / a_wall / 1e6,
              b_name.c_str(), median(b_rate) / 1e6, double(b_samples) / b_wall / 1e6, b_name.c_str(),
              a_name.c_str(), median(ratio), quantile(ratio, 0.25), quantile(ratio, 0.75));
}

}  // namespace

/// The renderer's samples and rays per second over whole tiles for about `seconds`, against
/// Embree's raw rate (`raw`) and the widest packet's per-CPU-second rate (0: not measured).
void measure_renderer(const Renderer& renderer, const JobOptions& options, uint32_t spp, double seconds,
                      const Rate& raw, double packet_cpu_rate) {
  const double raw_rate = raw.wall;
  RenderStats stats;
  timespec cpu0, cpu1;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &cpu0);
  auto t0 = std::chrono::steady_clock::now();
  uint32_t batch = 0;
  const std::vector<TileRect> tiles = options.plan().tiles();
  // Stops at the first tile boundary past `seconds`, so a large image at a high --spp does not
  // run a whole batch of the frame on a loaded machine (the figure then covers the tiles reached).
  bool done = false;
  while (!done) {
    for (const TileRect& tile : tiles) {
      renderer.render(tile, batch * spp, (batch + 1) * spp, &stats);
      if ((done = seconds_since(t0) >= seconds)) break;
    }
    ++batch;
  }
  const double elapsed = seconds_since(t0);
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &cpu1);
  const double cpu = double(cpu1.tv_sec - cpu0.tv_sec) + 1e-9 * double(cpu1.tv_nsec - cpu0.tv_nsec);
  const double render_rays = double(stats.rays + stats.shadow_rays) / elapsed;
  std::printf("renderer: %.2f M samples/s, %.2f M rays/s (closest-hit %.2f M/s + shadow %.2f M/s), "
              "%.1f %% of the raw rate\n",
              double(stats.samples) / elapsed / 1e6, render_rays / 1e6, double(stats.rays) / elapsed / 1e6,
              double(stats.shadow_rays) / elapsed / 1e6, 100.0 * render_rays / raw_rate);
  std::printf("renderer per CPU-second (all its threads): %.2f M rays, %.1f %% of the raw per-CPU-second rate\n",
              double(stats.rays + stats.shadow_rays) / cpu / 1e6,
              100.0 * double(stats.rays + stats.shadow_rays) / cpu / raw.cpu);
  if (packet_cpu_rate > 0) {
    std::printf("renderer per CPU-second: %.1f %% of the widest packet's closest-hit rate\n",
                100.0 * double(stats.rays + stats.shadow_rays) / cpu / packet_cpu_rate);
  }
}

int main(int argc, char** argv) {
  CLI::App app{"Embree's raw ray throughput against the renderer's, on one scene"};
  std::string scene_file;
  double seconds = 5;
  int threads = 0;
  uint32_t spp = 16;
  app.add_option("scene", scene_file, "Scene file")->required();
  app.add_option("--seconds", seconds, "Time per measurement");
  app.add_option("--threads", threads, "Threads (default: all cores)");
  app.add_option("--spp", spp, "Samples per pixel per renderer batch");
  std::string mode = "scalar";
  std::vector<int> widths = {1, 8, 16};
  std::string isa;
  app.add_option("--mode", mode, "scalar: TraceableScene::intersect and the renderer; packet: also the "
                                 "packet tracer at each --widths")
      ->check(CLI::IsMember({"scalar", "packet"}));
  app.add_option("--widths", widths, "Packet widths for --mode packet (1 = rtcIntersect1)")
      ->delimiter(',')
      ->check(CLI::IsMember({1, 4, 8, 16}));
  int rounds = 3;
  app.add_option("--rounds", rounds, "--mode packet: rounds of every query, interleaved; medians printed")
      ->check(CLI::PositiveNumber);
  app.add_option("--isa", isa, "Pin Embree's instruction set (avx512, avx2, sse4.2)");
  std::string integrator = "wavefront";
  app.add_option("--integrator", integrator, "The renderer's integrator (renderer.h)")
      ->check(CLI::IsMember({"scalar", "wavefront", "both"}));
  std::vector<std::string> kernels = {"auto"};
  app.add_option("--kernel-isa", kernels,
                 "Instruction set of the wavefront loop (auto, baseline, avx2, avx512); two, comma-separated "
                 "(baseline,avx512): both alternating tile by tile, their per-tile ratio printed")
      ->delimiter(',')
      ->expected(1, 2)
      ->check(CLI::IsMember({"auto", "baseline", "avx2", "avx512"}));
  CLI11_PARSE(app, argc, argv);
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // each figure shows as soon as it is measured
  std::optional<tbb::global_control> limit;
  if (threads > 0) limit.emplace(tbb::global_control::max_allowed_parallelism, size_t(threads));

  const Scene scene = load_scene_file(scene_file);
  JobOverrides overrides;
  overrides.spp = spp;
  overrides.max_depth = 8;
  const JobOptions options = resolve_job_options(scene, overrides);
  const TraceableScene traceable(scene, options.width, options.height, isa);
  const std::vector<Ray> rays = make_rays(traceable, options.width, options.height, 1 << 20);

  std::atomic<uint64_t> hits{0};
  uint64_t passes = 0;
  const auto scalar = [&] {
    return rate(rays.size(), seconds, [&](size_t begin, size_t end) {
      uint64_t local = 0;
      for (size_t i = begin; i != end; ++i) {
        Hit hit;
        local += traceable.intersect(rays[i], &hit) ? 1 : 0;
      }
      hits += local;
    }, &passes);
  };
  const Rate raw = scalar();
  const double raw_rate = raw.wall;
  std::printf("scene %s, isa %s\n", scene_file.c_str(), traceable.isa().c_str());
  std::printf("embree raw closest-hit rays: %.2f M rays/s, %.2f M rays per CPU-second (%zu rays in the pool, "
              "%.1f %% hit)\n",
              raw_rate / 1e6, raw.cpu / 1e6, rays.size(), 100.0 * double(hits) / double(passes * rays.size()));
  const double packet_cpu_rate = mode == "packet" ? packet_rates(traceable, rays, widths, seconds, rounds, scalar) : 0;

  const KernelIsa kernel = kernel_isa_from_name(kernels.front());
  if (kernels.size() == 2) {
    const Renderer a(scene, options, {}, IntegratorKind::wavefront, kernel);
    const Renderer b(scene, options, {}, IntegratorKind::wavefront, kernel_isa_from_name(kernels.back()));
    compare_renderers(a, "kernel " + a.kernel_isa(), b, "kernel " + b.kernel_isa(), "wavefront kernels", options,
                      spp, seconds);
    return 0;
  }
  if (integrator == "both") {
    const Renderer scalar(scene, options, {}, IntegratorKind::scalar);
    const Renderer wavefront(scene, options, {}, IntegratorKind::wavefront, kernel);
    compare_renderers(scalar, "scalar", wavefront, "wavefront", "integrators", options, spp, seconds);
    return 0;
  }
  const Renderer renderer(scene, options, {}, integrator_kind_from_name(integrator), kernel);
  std::printf("renderer integrator: %s, kernel %s\n", integrator_kind_name(renderer.integrator()),
              renderer.kernel_isa().c_str());
  measure_renderer(renderer, options, spp, seconds, raw, packet_cpu_rate);
  return 0;
}
