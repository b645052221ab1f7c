// tessera-bench-diffuse SCENE --integrator full|diffuse [--width W --height H --spp N]
//                      [--runs R] [--threads T]
//
// Does supporting mirrors and glass cost a scene that has neither? Glass and mirrors were in the
// renderer from its first commit (06f554a), so there is no "before" version to check out. This
// benchmark therefore carries `diffuse_trace_path`: the integrator exactly as it would be
// without mirror and glass support (trace_path of worker/render/integrator.cpp with the
// specular branches, the eta^2 bookkeeping and the material-type tests removed, nothing else
// changed), and renders a diffuse-only scene with it or with the renderer's own trace_path,
// single-threaded by default so that `valgrind --tool=callgrind` counts are repeatable.
// Both must give the same bits (checked: the sum over all samples is printed with 17 digits).
// BENCHMARKS.md, "Model only what a scene requires", has the commands and figures.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <glm/geometric.hpp>

#include "render/frame.h"
#include "render/integrator.h"
#include "render/traceable_scene.h"
#include "render/warp.h"
#include "scene/scene_loader.h"

using namespace tessera;

namespace {

// --- The integrator without mirror and glass (copied from integrator.cpp, specular removed) ---

constexpr uint32_t kPairsPerVertex = 3;
constexpr int kRouletteVertex = 3;
constexpr float kMaxSurvival = 0.95f;

float max_component(glm::vec3 v) { return std::max(v.x, std::max(v.y, v.z)); }

glm::vec3 emitted(const Geometry& g, glm::vec3 ng, glm::vec3 w) {
  if (g.emitter < 0) return glm::vec3(0.0f);
  if (glm::dot(ng, w) > 0 || g.two_sided_emission) return g.emission;
  return glm::vec3(0.0f);
}

glm::dvec3 sample_direct(const TraceableScene& scene, const SurfacePoint& sp, glm::vec3 origin,
                         glm::vec3 ns, glm::vec3 albedo, glm::vec2 u_pick, glm::vec2 u_point,
                         PathCounters& counters) {
  float pick_pmf = 0;
  const uint32_t index = scene.light_selector().pick(u_pick.x, &pick_pmf);
  const Emitter& emitter = scene.emitters()[index];
  const EmitterSample ls = emitter.sample(u_point);
  const glm::vec3 to_light = ls.sp.p - sp.p;
  const float dist2 = glm::dot(to_light, to_light);
  if (!(dist2 > 0)) return glm::dvec3(0.0);
  const glm::vec3 wi = to_light / std::sqrt(dist2);
  const float cos_surface = glm::dot(ns, wi);
  if (cos_surface <= 0 || glm::dot(sp.ng, wi) <= 0) return glm::dvec3(0.0);
  const glm::vec3 le = emitted(emitter.geometry(), ls.sp.ng, -wi);
  const float cos_light = std::abs(glm::dot(ls.sp.ng, wi));
  if (le == glm::vec3(0.0f) || cos_light <= 0) return glm::dvec3(0.0);
  const glm::vec3 from = origin;
  const glm::vec3 to = offset_ray_origin(ls.sp, -wi);
  ++counters.shadow_rays;
  if (scene.occluded(from, to - from, 1.0f)) return glm::dvec3(0.0);
  const double geometry =
      double(cos_surface) * double(cos_light) / (double(dist2) * double(ls.pdf_area) * pick_pmf);
  return glm::dvec3(albedo) * glm::dvec3(le) * (geometry / 3.14159265358979323846);
}

glm::dvec3 diffuse_trace_path(const TraceableScene& scene, Ray ray, int max_depth,
                              PixelSampler& sampler, PathCounters& counters) {
  glm::dvec3 radiance(0.0);
  glm::vec3 beta(1.0f);
  bool count_emission = true;  // the camera ray only: every bounce is diffuse
  const bool have_lights = !scene.emitters().empty();
  for (int vertex = 0;; ++vertex) {
    Hit hit;
    ++counters.rays;
    if (!scene.intersect(ray, &hit)) break;
    const glm::vec3 wo = -ray.d;
    const Geometry& g = *hit.geometry;
    if (count_emission) {
      const glm::vec3 le = emitted(g, hit.sp.ng, wo);
      if (le != glm::vec3(0.0f)) radiance += glm::dvec3(beta) * glm::dvec3(le);
    }
    if (max_depth >= 0 && vertex + 2 > max_depth) break;
    const uint32_t pair = kCameraPairs + kPairsPerVertex * uint32_t(vertex);
    const bool roulette = vertex + 1 >= kRouletteVertex;
    glm::vec2 u_choice(0.0f), u_light(0.0f);
    if (roulette || have_lights) {
      sampler.set_pair(pair);
      u_choice = sampler.get2d_independent();
    }
    if (have_lights) {
      sampler.set_pair(pair + 1);
      u_light = sampler.get2d();
    }
    sampler.set_pair(pair + 2);
    const glm::vec2 u_scatter = sampler.get2d();

    const RenderMaterial& m = scene.material(g.material);
    SurfacePoint sp = hit.sp;
    glm::vec3 ns = hit.ns;
    if (!(glm::dot(wo, sp.ng) > 0)) {
      if (!m.two_sided) break;
      sp.ng = -sp.ng;
      ns = -ns;
    }
    const glm::vec3 origin = offset_ray_origin(sp, sp.ng);
    if (have_lights) {
      radiance += glm::dvec3(beta) *
                  sample_direct(scene, sp, origin, ns, m.albedo, u_choice, u_light, counters);
    }
    const glm::vec3 wi = Frame(ns).to_world(square_to_cosine_hemisphere(u_scatter));
    if (glm::dot(wi, sp.ng) <= 0) break;
    beta *= m.albedo;
    count_emission = false;
    if (beta == glm::vec3(0.0f)) break;
    if (roulette) {
      const float survival = std::min(max_component(beta), kMaxSurvival);
      if (u_choice.y >= survival) break;
      beta /= survival;
    }
    ray.o = origin;
    ray.d = wi;
    ray.t_max = std::numeric_limits<float>::infinity();
  }
  return radiance;
}

// --- The render loop (as Renderer::render, one image, no tiles) ------------------------------

struct Totals {
  double sum = 0;  ///< all samples' R + G + B
  uint64_t rays = 0, shadow_rays = 0;
};

/// Renders every pixel's samples [0, spp) with `trace`; rows in parallel, each row's sum kept
/// apart and added in row order, so the total does not depend on the thread count.
template <typename Trace>
__attribute__((noinline)) Totals render_image(const TraceableScene& scene, int width, int height,
                                              uint32_t spp, int max_depth, Trace trace) {
  std::vector<double> row_sums(static_cast<size_t>(height), 0.0);
  std::vector<PathCounters> row_counters(static_cast<size_t>(height));
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y != rows.end(); ++y) {
      double sum = 0;
      for (int x = 0; x < width; ++x) {
        const uint64_t key = PixelSampler::pixel_key(0, x, y);
        for (uint32_t s = 0; s < spp; ++s) {
          PixelSampler sampler(key, s);
          const glm::vec2 u_film = sampler.get2d();
          const glm::vec2 u_lens = sampler.get2d();
          const Ray ray = scene.camera().generate_ray({float(x) + u_film.x, float(y) + u_film.y}, u_lens);
          const glm::dvec3 l = trace(scene, ray, max_depth, sampler, row_counters[size_t(y)]);
          sum += l.x + l.y + l.z;
        }
      }
      row_sums[size_t(y)] = sum;
    }
  });
  Totals t;
  for (int y = 0; y < height; ++y) {
    t.sum += row_sums[size_t(y)];
    t.rays += row_counters[size_t(y)].rays;
    t.shadow_rays += row_counters[size_t(y)].shadow_rays;
  }
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"The renderer's integrator against the same integrator without mirror and glass, on a diffuse-only scene"};
  std::string scene_file, integrator = "full";
  int width = 64, height = 64, runs = 1, threads = 1, max_depth = -1;
  uint32_t spp = 16;
  app.add_option("scene", scene_file, "A scene whose materials are all diffuse")->required();
  app.add_option("--integrator", integrator, "full (the renderer's trace_path) or diffuse (without mirror and glass)")
      ->check(CLI::IsMember({"full", "diffuse"}));
  app.add_option("--width", width, "Image width")->check(CLI::PositiveNumber);
  app.add_option("--height", height, "Image height")->check(CLI::PositiveNumber);
  app.add_option("--spp", spp, "Samples per pixel")->check(CLI::PositiveNumber);
  app.add_option("--max-depth", max_depth, "Mitsuba's convention, -1 = unbounded");
  app.add_option("--runs", runs, "Timed repetitions (the median is printed)")->check(CLI::PositiveNumber);
  app.add_option("--threads", threads, "Threads (default 1, for callgrind)")->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);

  try {
    Scene scene = load_scene_file(scene_file);
    for (const Shape& shape : scene.shapes) {
      if (scene.materials[shape.material].type != MaterialType::diffuse) {
        std::fprintf(stderr, "tessera-bench-diffuse: %s: %s is not diffuse; the comparison needs a diffuse-only scene\n",
                     scene_file.c_str(), shape.origin.c_str());
        return 1;
      }
    }
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    const TraceableScene traceable(scene, width, height, "");
    std::vector<double> times;
    Totals totals;
    for (int r = 0; r < runs; ++r) {
      const auto t0 = std::chrono::steady_clock::now();
      totals = integrator == "full" ? render_image(traceable, width, height, spp, max_depth, trace_path)
                                    : render_image(traceable, width, height, spp, max_depth, diffuse_trace_path);
      times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    std::vector<double> sorted = times;
    std::sort(sorted.begin(), sorted.end());
    const double median = sorted.size() % 2 ? sorted[sorted.size() / 2]
                                            : 0.5 * (sorted[sorted.size() / 2 - 1] + sorted[sorted.size() / 2]);
    std::printf("integrator %s: %dx%d, %u spp, %d thread(s): sum of all samples %.17g, %llu rays, %llu shadow rays\n",
                integrator.c_str(), width, height, spp, threads, totals.sum,
                static_cast<unsigned long long>(totals.rays), static_cast<unsigned long long>(totals.shadow_rays));
    std::printf("times (s):");
    for (double t : times) std::printf(" %.3f", t);
    std::printf("\nmedian %.3f s\n", median);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tessera-bench-diffuse: %s\n", e.what());
    return 1;
  }
  return 0;
}
