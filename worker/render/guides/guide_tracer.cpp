#include "render/guides/guide_tracer.h"

#include <cmath>

#include <glm/common.hpp>

#include "render/integrators/integrator.h"
#include "render/integrators/vertex_shading.h"

namespace tessera {

GuideSample trace_guide(const TraceableScene& scene, Ray ray, PixelSampler& sampler) {
  using namespace path_vertex_detail;
  glm::vec3 tint(1.0f);
  for (int vertex = 0; vertex <= kMaxGuideSpecularVertices; ++vertex) {
    Hit hit;
    if (!scene.intersect(ray, &hit)) return {};
    const glm::vec3 wo = -ray.d;
    SurfacePoint sp = hit.sp;
    const RenderMaterial* m = facing_material(scene, &scene.material(hit.geometry->material), wo, sp, hit);
    if (!m) return {glm::vec3(0.0f), hit.ns};  // black from behind
    const ShadingFrame shading = shading_frame(hit, *m, scene.textures(), scene.has_uv(), wo);
    const glm::vec3 wo_local = shading.frame.to_local(wo);
    const Bsdf bsdf(bsdf_params(*m, scene.textures(), texture_point(hit)));
    // The colour path's pairs at this vertex: the lobe from pair + 3's x, the direction pair + 2.
    const uint32_t pair = kCameraPairs + kPairsPerVertex * uint32_t(vertex);
    sampler.set_pair(pair + 3);
    const float u_lobe = sampler.get2d_x();
    sampler.set_pair(pair + 2);
    const glm::vec2 u = sampler.get2d();
    const std::optional<BsdfSample> bs = bsdf.sample(wo_local, u_lobe, u);
    if (bsdf.has_smooth_lobe() || !bs || !bs->delta) {
      glm::vec3 albedo = bs ? tint * glm::clamp(bs->weight, 0.0f, 1.0f) : glm::vec3(0.0f);
      if (!std::isfinite(albedo.x + albedo.y + albedo.z)) albedo = glm::vec3(0.0f);
      return {albedo, shading.frame.n};
    }
    const std::optional<ScatteredDirection> out = scattered_direction(shading, *bs, *m, sp);
    if (!out) return {};
    // eta^2 undoes a refraction's radiance scaling: the tint is the surface's transmittance.
    tint *= glm::clamp(bs->weight * (out->perturbation * bs->eta * bs->eta), 0.0f, 1.0f);
    ray = Ray{offset_ray_origin(sp, out->wi), out->wi};
  }
  return {};
}

}  // namespace tessera
