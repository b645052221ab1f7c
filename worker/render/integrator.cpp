#include "integrator.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "fresnel.h"
#include "frame.h"
#include "warp.h"

namespace tessera {
namespace {

/// Dimension pairs per path vertex: (light choice, roulette), light point, scattering.
constexpr uint32_t kPairsPerVertex = 3;
/// Russian roulette starts at this vertex (0 = the camera ray's hit).
constexpr int kRouletteVertex = 3;
constexpr float kMaxSurvival = 0.95f;

float max_component(glm::vec3 v) { return std::max(v.x, std::max(v.y, v.z)); }

/// The radiance an emitter sends from its surface point with normal `ng` towards `w`.
glm::vec3 emitted(const Geometry& g, glm::vec3 ng, glm::vec3 w) {
  if (g.emitter < 0) return glm::vec3(0.0f);
  if (glm::dot(ng, w) > 0 || g.two_sided_emission) return g.emission;
  return glm::vec3(0.0f);
}

/// Next-event estimation at a Lambertian point: f * Le * G / pdf for one sampled light point,
/// or zero when it is occluded or faces away.
/// `origin` is sp offset to the front side (where every direction it accepts points).
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

  // (albedo / pi) * Le * cos_surface * cos_light / dist^2 / (pdf_area * pick_pmf), in double so
  // that tiny, bright lights cannot overflow float.
  const double geometry =
      double(cos_surface) * double(cos_light) / (double(dist2) * double(ls.pdf_area) * pick_pmf);
  return glm::dvec3(albedo) * glm::dvec3(le) * (geometry / 3.14159265358979323846);
}

/// Perfect mirror or glass at a hit seen from `wo`: picks the outgoing direction `wi`, turns
/// `sp` and `ns` to the side the path arrives from, and updates the throughput and the eta^2
/// product. Returns false when the path ends (a one-sided mirror seen from behind, or a mirror
/// direction under the geometric surface).
bool scatter_specular(const RenderMaterial& m, glm::vec3 wo, bool front, glm::vec2 u_scatter,
                      SurfacePoint& sp, glm::vec3& ns, glm::vec3& beta, float& eta_scale,
                      glm::vec3& wi) {
  if (m.type == MaterialType::glass) {
    // Glass is two-sided by nature: entering from the front, leaving from the back.
    const float eta = front ? m.ior : 1.0f / m.ior;
    if (!front) {
      sp.ng = -sp.ng;
      ns = -ns;
    }
    float cos_t = 0;
    const float reflectance = fresnel_dielectric(glm::dot(wo, ns), eta, &cos_t);
    if (u_scatter.x < reflectance) {
      wi = reflect(wo, ns);
    } else {
      wi = refract(wo, ns, eta, cos_t);
      // Radiance is compressed by eta^2 when it enters a denser medium (non-symmetric
      // scattering: pbrt-v4 section 9.5.2).
      beta /= eta * eta;
      eta_scale *= eta * eta;
    }
    return true;
  }
  if (!front) {
    if (!m.two_sided) return false;  // one-sided surfaces are black from behind
    sp.ng = -sp.ng;
    ns = -ns;
  }
  wi = reflect(wo, ns);
  return glm::dot(wi, sp.ng) > 0;
}

}  // namespace

glm::dvec3 trace_path(const TraceableScene& scene, Ray ray, int max_depth, PixelSampler& sampler,
                      PathCounters& counters) {
  glm::dvec3 radiance(0.0);
  glm::vec3 beta(1.0f);
  float eta_scale = 1.0f;        // product of eta^2 over refractions, undone for roulette
  bool count_emission = true;    // camera ray or a perfectly specular bounce
  const bool have_lights = !scene.emitters().empty();

  for (int vertex = 0;; ++vertex) {
    Hit hit;
    ++counters.rays;
    if (!scene.intersect(ray, &hit)) break;
    const glm::vec3 wo = -ray.d;  // every ray the integrator spawns has a unit direction
    const Geometry& g = *hit.geometry;

    if (count_emission) {
      const glm::vec3 le = emitted(g, hit.sp.ng, wo);
      if (le != glm::vec3(0.0f)) radiance += glm::dvec3(beta) * glm::dvec3(le);
    }
    // Vertex `vertex` closes segment vertex + 1; scattering here would add one more.
    if (max_depth >= 0 && vertex + 2 > max_depth) break;

    // Each pair is drawn only where it is used (a pure function of its pair index, so the
    // numbers are the same as drawing all three): no light-sampling numbers at mirror and glass
    // vertices or in a scene without emitters, no roulette number before roulette starts.
    const uint32_t pair = kCameraPairs + kPairsPerVertex * uint32_t(vertex);
    const bool roulette = vertex + 1 >= kRouletteVertex;
    const RenderMaterial& m = scene.material(g.material);
    SurfacePoint sp = hit.sp;
    glm::vec3 ns = hit.ns;
    const bool front = glm::dot(wo, sp.ng) > 0;
    glm::vec2 u_choice(0.0f);
    glm::vec3 wi, origin;

    if (m.type == MaterialType::diffuse) {
      // The common case first, with nothing of the specular materials in its way.
      if (!front) {
        if (!m.two_sided) break;  // one-sided surfaces are black from behind
        sp.ng = -sp.ng;
        ns = -ns;
      }
      // Both the shadow ray and the bounce leave on the front side: one offset serves both.
      origin = offset_ray_origin(sp, sp.ng);
      if (roulette || have_lights) {
        sampler.set_pair(pair);
        u_choice = sampler.get2d_independent();
      }
      if (have_lights) {
        sampler.set_pair(pair + 1);
        const glm::vec2 u_light = sampler.get2d();
        radiance += glm::dvec3(beta) *
                    sample_direct(scene, sp, origin, ns, m.albedo, u_choice, u_light, counters);
      }
      sampler.set_pair(pair + 2);
      wi = Frame(ns).to_world(square_to_cosine_hemisphere(sampler.get2d()));
      if (glm::dot(wi, sp.ng) <= 0) break;
      beta *= m.albedo;  // f * cos / pdf = (albedo / pi) * cos / (cos / pi)
      count_emission = false;
    } else {
      if (roulette) {
        sampler.set_pair(pair);
        u_choice = sampler.get2d_independent();
      }
      sampler.set_pair(pair + 2);
      if (!scatter_specular(m, wo, front, sampler.get2d(), sp, ns, beta, eta_scale, wi)) break;
      origin = offset_ray_origin(sp, wi);
      count_emission = true;
    }
    if (beta == glm::vec3(0.0f)) break;

    if (roulette) {
      const float survival = std::min(max_component(beta) * eta_scale, kMaxSurvival);
      if (u_choice.y >= survival) break;
      beta /= survival;
    }
    ray.o = origin;
    ray.d = wi;
    ray.t_max = std::numeric_limits<float>::infinity();
  }
  return radiance;
}

}  // namespace tessera
