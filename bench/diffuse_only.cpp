// tessera-bench-diffuse SCENE --integrator full|diffuse [--width W --height H --spp N]
//                      [--runs R] [--threads T]
//
// Does supporting mirrors, glass, textures and masks cost a scene that has none? They have been
// in the renderer from early on, so there is no "before" version to check out. This benchmark
// therefore carries `diffuse_trace_path`: the integrator as it would be with constant diffuse
// materials alone (trace_path of worker/render/integrators/integrator.cpp with every other material, masks,
// textures, environments and the eta^2 bookkeeping removed, nothing else changed: the same
// LightSet calls, MIS weights and dimension layout), and renders a diffuse-only scene with it or
// with the renderer's own trace_path, single-threaded by default so that
// `valgrind --tool=callgrind` counts are repeatable. Both must give the same bits (checked: the
// sum over all samples is printed with 17 digits). BENCHMARKS.md, "Model only what a scene
// requires", has the commands and figures.
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

#include "render/integrators/integrator.h"
#include "render/integrators/path_vertex.h"
#include "render/math/frame.h"
#include "render/sampling/warp.h"
#include "render/scene/traceable_scene.h"
#include "scene/loader/scene_loader.h"

using namespace tessera;

namespace {

// --- The integrator without mirror and glass (copied from integrator.cpp, specular removed) ---
// The same light sampling (LightSet, MIS on emitters hit by bounces), the same dimension layout
// and the same arithmetic as trace_path's diffuse branch, so both give the same bits; what is
// left out is every material but constant diffuse, masks, textures, environments,
// hide_emitters and the eta^2 bookkeeping of refraction.

constexpr uint32_t kPairsPerVertex = 4;
constexpr int kRouletteVertex = 3;
constexpr float kMaxSurvival = 0.95f;

float max_component(glm::vec3 v) { return std::max(v.x, std::max(v.y, v.z)); }

float mis_weight(float pdf_a, float pdf_b) {
  const float a = pdf_a * pdf_a, b = pdf_b * pdf_b;
  const float w = a / (a + b);
  return std::isfinite(w) ? w : 0.0f;
}

bool unoccluded(const TraceableScene& scene, glm::vec3 origin, const LightSample& ls,
                PathCounters& counters) {
  ++counters.shadow_rays;
  ShadowQuery q;
  path_vertex_detail::set_shadow_ray(origin, ls, &q);  // the renderer's own shadow ray, so both end it alike
  return !scene.occluded(q.o, q.d, q.t_max);
}

glm::dvec3 diffuse_trace_path(const TraceableScene& scene, Ray ray, int max_depth,
                              PixelSampler& sampler, PathCounters& counters) {
  const LightSet& lights = scene.lights();
  const bool have_lights = !lights.empty();
  glm::dvec3 radiance(0.0);
  glm::vec3 beta(1.0f);
  bool prev_delta = true;  // the camera ray
  float prev_pdf = 0;
  SurfacePoint prev_sp{};
  for (int vertex = 0;; ++vertex) {
    Hit hit;
    ++counters.rays;
    if (!scene.intersect(ray, &hit)) break;
    const glm::vec3 wo = -ray.d;
    const Geometry& g = *hit.geometry;
    if (g.emitter >= 0) {
      const glm::vec3 le = lights.emitted(g, hit.primitive, hit.uv, hit.sp.ng, wo);
      if (le != glm::vec3(0.0f)) {
        const float w = prev_delta ? 1.0f
                                   : mis_weight(prev_pdf, lights.pdf_area(g, hit.primitive, prev_sp, hit.sp.p, hit.sp.ng));
        radiance += glm::dvec3(beta) * glm::dvec3(le) * double(w);
      }
    }
    if (max_depth >= 0 && vertex + 2 > max_depth) break;
    const uint32_t pair = kCameraPairs + kPairsPerVertex * uint32_t(vertex);
    const bool roulette = vertex + 1 >= kRouletteVertex;
    const RenderMaterial* m = &scene.material(g.material);
    SurfacePoint sp = hit.sp;
    glm::vec3 ns = hit.ns;
    if (!(glm::dot(wo, sp.ng) > 0)) {
      if (m->back >= 0) {
        m = &scene.material(uint32_t(m->back));
      } else if (!m->two_sided) {
        break;
      }
      sp.ng = -sp.ng;
      ns = -ns;
    }
    const glm::vec3 origin = offset_ray_origin(sp, sp.ng);
    glm::vec2 u_choice(0.0f);
    if (roulette || have_lights) {
      sampler.set_pair(pair);
      u_choice = sampler.get2d_independent();
    }
    if (have_lights) {
      sampler.set_pair(pair + 1);
      const LightSample ls = lights.sample(sp, u_choice.x, sampler.get2d());
      if (ls.pdf > 0) {
        const float cos_surface = glm::dot(ns, ls.wi);
        if (cos_surface > 0 && glm::dot(sp.ng, ls.wi) > 0 && ls.radiance != glm::vec3(0.0f) &&
            unoccluded(scene, origin, ls, counters)) {
          const float w = ls.delta ? 1.0f : mis_weight(ls.pdf, cos_surface * kInvPi);
          radiance += glm::dvec3(beta) * glm::dvec3(m->albedo) * glm::dvec3(ls.radiance) *
                      (double(cos_surface) * double(kInvPi) * double(w) / double(ls.pdf));
        }
      }
    }
    sampler.set_pair(pair + 2);
    const glm::vec3 local = square_to_cosine_hemisphere(sampler.get2d());
    const glm::vec3 wi = Frame(ns).to_world(local);
    if (glm::dot(wi, sp.ng) <= 0) break;
    beta *= m->albedo;
    if (!(max_component(beta) > 0)) break;
    if (roulette) {
      const float survival = std::min(max_component(beta), kMaxSurvival);
      if (u_choice.y >= survival) break;
      beta /= survival;
    }
    prev_delta = false;
    prev_pdf = local.z * kInvPi;
    prev_sp = sp;
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
    // What diffuse_trace_path leaves out must be absent, or the two would differ.
    for (const Material& m : scene.materials) {
      if (m.type != MaterialType::diffuse) {
        std::fprintf(stderr, "tessera-bench-diffuse: %s: material \"%s\" is not diffuse; the comparison needs a diffuse-only scene\n",
                     scene_file.c_str(), m.name.c_str());
        return 1;
      }
    }
    for (const Light& light : scene.lights) {
      if (light.kind == LightKind::constant || light.kind == LightKind::envmap) {
        std::fprintf(stderr, "tessera-bench-diffuse: %s: %s is an environment light, which the diffuse-only integrator leaves out\n",
                     scene_file.c_str(), light.origin.c_str());
        return 1;
      }
    }
    if (scene.render.hide_emitters) {
      std::fprintf(stderr, "tessera-bench-diffuse: %s: hide_emitters is set, which the diffuse-only integrator leaves out\n",
                   scene_file.c_str());
      return 1;
    }
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    const TraceableScene traceable(scene, width, height, "");
    for (uint32_t i = 0; i < scene.materials.size(); ++i) {
      const RenderMaterial& m = traceable.material(i);
      if (m.textured || m.masked()) {
        std::fprintf(stderr, "tessera-bench-diffuse: %s: material \"%s\" is textured or masked; the comparison needs constant diffuse materials\n",
                     scene_file.c_str(), scene.materials[i].name.c_str());
        return 1;
      }
    }
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
