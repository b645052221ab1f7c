#include "render/integrators/integrator.h"

#include "render/integrators/path_vertex.h"

namespace tessera {

glm::dvec3 trace_path(const TraceableScene& scene, Ray ray, int max_depth, PixelSampler& sampler,
                      PathCounters& counters) {
  PathState path{ray};
  for (;;) {
    Hit hit;
    ++counters.rays;
    // A copy, so that `path` itself never has its address taken and stays in registers.
    const Ray ray_copy = path.ray;
    const bool found = scene.intersect(ray_copy, &hit);
    ShadowQuery shadow;
    bool has_shadow;
    const bool goes_on = path_vertex(scene, max_depth, sampler, path, found ? &hit : nullptr, &shadow, &has_shadow);
    if (has_shadow) {
      ++counters.shadow_rays;
      if (!scene.occluded(shadow.o, shadow.d, shadow.t_max)) path.radiance += shadow.contribution;
    }
    if (!goes_on) break;
  }
  return path.radiance;
}

}  // namespace tessera
