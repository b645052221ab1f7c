#include "render/wavefront/wavefront_integrator.h"

#include <string>

#include <stdexcept>

namespace tessera {

WavefrontIntegrator::WavefrontIntegrator(const TraceableScene& scene, int max_depth, int packet_width)
    : scene_(scene), max_depth_(max_depth), tracer_(scene.embree_scene(), packet_width) {}

void WavefrontIntegrator::trace(std::vector<PathState>& paths, std::vector<PixelSampler>& samplers,
                                PathCounters& counters, Workspace& workspace) const {
  if (samplers.size() != paths.size()) {
    throw std::invalid_argument("WavefrontIntegrator::trace: " + std::to_string(paths.size()) + " paths but " +
                                std::to_string(samplers.size()) + " samplers");
  }
  const size_t n = paths.size();
  RayBatch& rays = workspace.rays;
  RayBatch& shadow_rays = workspace.shadow_rays;
  HitBatch& hits = workspace.hits;
  std::vector<uint8_t>& occluded = workspace.occluded;
  std::vector<uint32_t>& live = workspace.live;
  std::vector<uint32_t>& next = workspace.next;
  std::vector<uint32_t>& shadow_path = workspace.shadow_path;
  std::vector<glm::dvec3>& shadow_contribution = workspace.shadow_contribution;
  live.resize(n);
  for (size_t i = 0; i < n; ++i) live[i] = uint32_t(i);

  while (!live.empty()) {
    const size_t count = live.size();
    rays.resize(count);
    hits.resize(count);
    for (size_t j = 0; j < count; ++j) rays.set(j, paths[live[j]].ray);
    tracer_.intersect(rays, 0, count, &hits);
    counters.rays += count;

    next.clear();
    shadow_path.clear();
    shadow_contribution.clear();
    shadow_rays.resize(count);
    for (size_t j = 0; j < count; ++j) {
      const uint32_t i = live[j];
      PathState& path = paths[i];
      Hit hit;
      const bool found = hits.geometry[j] != RTC_INVALID_GEOMETRY_ID;
      if (found) {
        scene_.make_hit(path.ray, hits.geometry[j], hits.instance[j], hits.primitive[j], hits.t[j], hits.u[j],
                        hits.v[j], &hit);
      }
      ShadowQuery shadow;
      bool has_shadow;
      if (path_vertex(scene_, max_depth_, samplers[i], path, found ? &hit : nullptr, &shadow, &has_shadow)) {
        next.push_back(i);
      }
      if (has_shadow) {
        shadow_rays.set(shadow_path.size(), Ray{shadow.o, shadow.d, shadow.t_max});
        shadow_path.push_back(i);
        shadow_contribution.push_back(shadow.contribution);
      }
    }

    const size_t shadows = shadow_path.size();
    if (shadows > 0) {
      occluded.resize(shadows);
      tracer_.occluded(shadow_rays, 0, shadows, &occluded);
      counters.shadow_rays += shadows;
      for (size_t k = 0; k < shadows; ++k) {
        if (!occluded[k]) paths[shadow_path[k]].radiance += shadow_contribution[k];
      }
    }
    live.swap(next);
  }
}

}  // namespace tessera
