#include "render/integrators/caustic_photons.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <tbb/parallel_for.h>

#include "render/bsdf/principled_lobes.h"
#include "render/guiding/target_mixture.h"
#include "render/integrators/vertex_shading.h"
#include "render/sampling/warp.h"

namespace tessera {
namespace {

using namespace path_vertex_detail;
using principled::luminance;

/// The numbers of photon `index` of stream `stream` (one per target), each in [0, 1): a key
/// hashed once from the two, then one mix per number (SplitMix64's sequence from the key), so a
/// photon's numbers depend on nothing but its index. Three mixes per number cost the build 4 %
/// more instructions.
class PhotonNumbers {
 public:
  PhotonNumbers(uint64_t stream, uint32_t index) : key_(mix64(hash_combine(stream, index))) {}
  float operator()(uint32_t dim) const {
    return float(splitmix64(key_ + (uint64_t(dim) + 1) * 0x9e3779b97f4a7c15ull) >> 40) * 0x1p-24f;
  }

 private:
  uint64_t key_;
};

/// The first surface along `ray` (t_max set to infinity here), turned to face where the ray
/// came from (vertex_shading.h's facing_material): false when the ray escapes or the surface is
/// black from that side.
struct FacingHit {
  Hit hit;
  SurfacePoint sp;
  const RenderMaterial* m = nullptr;
  glm::vec3 wo{0.0f};  ///< toward where the ray came from
};
bool next_surface(const TraceableScene& scene, Ray& ray, FacingHit* out) {
  ray.t_max = std::numeric_limits<float>::infinity();
  if (!scene.intersect(ray, &out->hit)) return false;
  out->wo = -ray.d;
  out->sp = out->hit.sp;
  out->m = facing_material(scene, &scene.material(out->hit.geometry->material), out->wo, out->sp, out->hit);
  return out->m != nullptr;
}

/// The irradiance one diffuse bounce brings to point p (normal n, facing where the light comes
/// from): CausticGuide::kIndirectSamples cosine-weighted directions, each landing on a surface
/// that reflects a light sample's radiance by its reflectance's luminance (a Lambertian
/// estimate, whatever the material; a specular or emitting surface, or nothing, brings none).
/// Numbers from a hash of `stream` (the cell's key).
float indirect_irradiance(const TraceableScene& scene, glm::vec3 p, glm::vec3 n, uint64_t stream) {
  const LightSet& lights = scene.lights();
  const Frame frame(n);
  double sum = 0;
  for (uint32_t i = 0; i < uint32_t(CausticGuide::kIndirectSamples); ++i) {
    const PhotonNumbers u(stream, i);
    Ray ray;
    ray.o = p + n * 1e-4f * std::max(1.0f, max_component(glm::abs(p)));
    ray.d = frame.to_world(square_to_cosine_hemisphere({u(0), u(1)}));
    FacingHit f;
    if (!next_surface(scene, ray, &f) || smooth_specular(*f.m) || f.hit.geometry->emitter >= 0) continue;
    const RenderMaterial* m = f.m;
    const SurfacePoint& sp = f.sp;
    const LightSample ls = lights.sample(sp, u(2), {u(3), u(4)});
    if (!(ls.pdf > 0)) continue;
    const float cos_light = glm::dot(ls.wi, sp.ng);
    if (!(cos_light > 0)) continue;
    ShadowQuery q;
    set_shadow_ray(offset_ray_origin(sp, ls.wi), ls, &q);
    if (scene.occluded(q.o, q.d, q.t_max)) continue;
    // Radiance leaving the hit toward p, (rho / pi) L cos / pdf, times the bounce's cos / pdf = pi.
    const float rho = luminance(m->type == MaterialType::diffuse && !m->textured ? m->albedo : m->reflectance.value);
    const double v = double(rho) * double(luminance(ls.radiance)) * double(cos_light) / double(ls.pdf);
    if (std::isfinite(v)) sum += v;
  }
  return float(sum / CausticGuide::kIndirectSamples);
}

/// The six axes, in turn, as the normal of the point the lights are sampled from: the light
/// picker weighs lights by the cosine toward that normal, and a photon's weight divides by the
/// density it was drawn with, so any normal gives a right weight; cycling through six lets
/// every light above or below the target be found.
const glm::vec3 kAxes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};

/// Photon `i` toward `target`: the ray it leaves along and its weight (its power over the
/// density it was drawn with); false when it carries nothing.
bool emit_photon(const TraceableScene& scene, const SpecularTarget& target, uint32_t i, const PhotonNumbers& u,
                 Ray* ray, float* weight) {
  const SurfacePoint centre{target.center, glm::vec3(0.0f), kAxes[i % 6]};
  const LightSample ls = scene.lights().sample(centre, u(0), {u(1), u(2)});
  if (!(ls.pdf > 0)) return false;
  const float power = luminance(ls.radiance);
  if (!(power > 0)) return false;
  if (std::isinf(ls.distance)) {
    // From a light at infinity: a parallel beam over the target's disc, starting on the disc's
    // plane tangent to the target on the light's side, if the light reaches it there.
    const Frame frame(ls.wi);
    const glm::vec2 disk = square_to_concentric_disk({u(3), u(4)});
    const glm::vec3 start =
        target.center + ls.wi * target.radius + frame.to_world(glm::vec3(disk * target.radius, 0.0f));
    if (scene.occluded(start, ls.wi, std::numeric_limits<float>::infinity())) return false;
    ray->o = start;
    ray->d = -ls.wi;
    // Radiance (or a directional light's irradiance) over the disc's area, per density.
    *weight = power * (kPi * target.radius * target.radius) / ls.pdf;
  } else {
    // From the light's point: a direction uniform in the cone of the target's sphere.
    const glm::vec3 y = ls.point.p;
    const glm::vec3 d = target.center - y;
    const float dist2 = glm::dot(d, d);
    const float r2 = target.radius * target.radius;
    if (!(dist2 > r2)) return false;
    const float inv_dist = 1.0f / std::sqrt(dist2);
    const float sin2 = std::min(r2 * (inv_dist * inv_dist), 1.0f);
    const float one_minus_cos = sin2 / (1.0f + std::sqrt(1.0f - sin2));
    const glm::vec3 dir = sample_uniform_cone(d * inv_dist, one_minus_cos, {u(3), u(4)});
    // A one-sided emitter sends nothing behind itself (point and spot lights: ng = -wi, which
    // every direction of the cone passes as the target is where wi points from).
    if (!ls.delta && glm::dot(dir, ls.point.ng) <= 0) return false;
    const float solid_angle = 2.0f * kPi * one_minus_cos;
    // Power = L cos dA dw: the area density is pdf cos / distance^2, the cosines cancel.
    *weight = power * solid_angle * (ls.distance * ls.distance) / ls.pdf;
    ray->o = offset_ray_origin(ls.point, dir);
    ray->d = dir;
  }
  return *weight > 0 && std::isfinite(*weight);
}

/// Follows a photon through smooth specular surfaces to the first other surface, where it is
/// deposited into `out` if it passed at least one specular vertex.
void follow_photon(const TraceableScene& scene, const CausticGuide& guide, const PhotonNumbers& u, Ray ray,
                   float weight, std::vector<CausticGuide::Deposit>& out) {
  glm::vec3 beta(1.0f);
  // vertex: the specular vertices passed so far (each loop that goes on passes one).
  for (uint32_t vertex = 0;; ++vertex) {
    FacingHit f;
    if (!next_surface(scene, ray, &f)) return;
    const RenderMaterial* m = f.m;
    const SurfacePoint& sp = f.sp;
    if (!smooth_specular(*m) || m->masked()) {
      if (vertex > 0) {
        float major;
        const float w = weight * luminance(beta);
        if (w > 0 && std::isfinite(w)) {
          out.push_back({guide.cell_key(sp.p, sp.ng), sp.p, sp.ng,
                         uint16_t(CausticGuide::direction_bin(f.wo, &major)), w});
        }
      }
      return;
    }
    if (vertex + 1 > uint32_t(CausticGuide::kMaxSpecularVertices)) return;
    const ShadingFrame shading = shading_frame(f.hit, *m, scene.textures(), scene.has_uv(), f.wo);
    const std::optional<BsdfSample> bs = specular_sample(*m, shading.frame.to_local(f.wo), u(5 + vertex));
    if (!bs) return;
    const std::optional<ScatteredDirection> next = scattered_direction(shading, *bs, *m, sp);
    if (!next) return;
    beta *= bs->weight * next->perturbation;
    if (!(max_component(beta) > 0)) return;
    ray.o = offset_ray_origin(sp, next->wi);
    ray.d = next->wi;
  }
}

/// Every photon's deposit, in (target, photon) order: in chunks of kChunk photons on every
/// thread of the caller's arena, the chunks joined in order, so the same list whatever ran where.
std::vector<CausticGuide::Deposit> trace_photons(const TraceableScene& scene, const CausticGuide& guide) {
  const SpecularTargets& targets = scene.specular_targets();
  constexpr uint32_t kChunk = 4096;
  constexpr uint32_t kChunksPerTarget = (CausticGuide::kPhotonsPerTarget + kChunk - 1) / kChunk;
  std::vector<std::vector<CausticGuide::Deposit>> chunks(size_t(targets.size()) * kChunksPerTarget);
  tbb::parallel_for(size_t(0), chunks.size(), [&](size_t c) {
    const int k = int(c / kChunksPerTarget);
    const SpecularTarget target = targets[k];
    const uint64_t stream = hash_combine(0x63617573746963ull, uint64_t(k));  // "caustic"
    const uint32_t first = uint32_t(c % kChunksPerTarget) * kChunk;
    const uint32_t last = std::min(first + kChunk, CausticGuide::kPhotonsPerTarget);
    for (uint32_t i = first; i < last; ++i) {
      const PhotonNumbers u(stream, i);
      Ray ray;
      float weight;
      if (emit_photon(scene, target, i, u, &ray, &weight)) follow_photon(scene, guide, u, ray, weight, chunks[c]);
    }
  });
  std::vector<CausticGuide::Deposit> deposits;
  for (const auto& chunk : chunks) deposits.insert(deposits.end(), chunk.begin(), chunk.end());
  return deposits;
}

}  // namespace

CausticGuide build_caustic_guide(const TraceableScene& scene) {
  const SpecularTargets& targets = scene.specular_targets();
  if (!TestSwitch<CausticGuide>::on() || targets.empty() || scene.lights().empty() || scene.has_media()) return {};

  float mean_radius = 0;
  for (int k = 0; k < targets.size(); ++k) mean_radius += targets[k].radius;
  mean_radius /= float(targets.size());
  if (!(mean_radius > 0) || !std::isfinite(mean_radius)) return {};
  // The cell's side, no smaller than the grid's reach allows: +-kGridHalf cells cover the scene
  // twice over, so that a tiny target in a large scene does not send most of the scene to the
  // grid's edge cells.
  const float cell_side = std::max(CausticGuide::kCellFraction * mean_radius,
                                   scene.reach() * (2.0f / float(CausticGuide::kGridHalf)));
  if (!std::isfinite(1.0f / cell_side)) return {};
  CausticGuide guide = CausticGuide::on_grid(cell_side);

  std::vector<CausticGuide::Deposit> deposits = trace_photons(scene, guide);
  const uint64_t deposited = deposits.size();
  const std::vector<CausticGuide::Candidate> candidates = CausticGuide::group(std::move(deposits));

  // Each cell's probability of a guided bounce: E_c from its photons (each target's photons
  // estimate the power into it, as the mean of their weights; the cell's area taken as a grid
  // square), E_i by one bounce from the cell's mean position. Only the cells kept get bins.
  const float power_to_irradiance = 1.0f / (float(CausticGuide::kPhotonsPerTarget) * cell_side * cell_side);
  std::vector<float> indirect(candidates.size());
  tbb::parallel_for(size_t(0), indirect.size(), [&](size_t c) {
    indirect[c] = indirect_irradiance(scene, candidates[c].position, candidates[c].normal, candidates[c].key);
  });
  guide.keep(candidates, indirect, power_to_irradiance, deposited);
  return guide;
}

}  // namespace tessera
