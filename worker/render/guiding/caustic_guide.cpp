#include "render/guiding/caustic_guide.h"

#include <limits>

#include <tbb/parallel_for.h>

#include "render/bsdf/principled_lobes.h"
#include "render/integrators/path_vertex.h"
#include "render/scene/traceable_scene.h"

namespace tessera {
namespace {

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

/// One photon's arrival at a diffuse surface after at least one specular vertex.
struct Deposit {
  uint64_t key;  ///< its cell
  glm::vec3 p;   ///< where it arrived
  glm::vec3 ng;  ///< the surface's normal there, toward where it came from
  uint16_t bin;  ///< the direction toward where it came from
  float weight;  ///< its power (luminance), up to a factor common to all photons
};

/// The first surface along `ray` (t_max set to infinity here), turned to face where the ray
/// came from (path_vertex.h's facing_material): false when the ray escapes or the surface is
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
  out->m = path_vertex_detail::facing_material(scene, &scene.material(out->hit.geometry->material), out->wo,
                                               out->sp, out->hit);
  return out->m != nullptr;
}

/// The irradiance one diffuse bounce brings to point p (normal n, facing where the light comes
/// from): CausticGuide::kIndirectSamples cosine-weighted directions, each landing on a surface
/// that reflects a light sample's radiance by its reflectance's luminance (a Lambertian
/// estimate, whatever the material; a specular or emitting surface, or nothing, brings none).
/// Numbers from a hash of `stream` (the cell's key).
float indirect_irradiance(const TraceableScene& scene, glm::vec3 p, glm::vec3 n, uint64_t stream) {
  using namespace path_vertex_detail;
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

}  // namespace

CausticGuide CausticGuide::build(const TraceableScene& scene, float scene_reach) {
  using namespace path_vertex_detail;
  CausticGuide guide;
  const SpecularTargets& targets = scene.specular_targets();
  const LightSet& lights = scene.lights();
  if (!TestSwitch<CausticGuide>::on() || targets.empty() || lights.empty() || scene.has_media()) return guide;

  float mean_radius = 0;
  for (int k = 0; k < targets.size(); ++k) mean_radius += targets[k].radius;
  mean_radius /= float(targets.size());
  if (!(mean_radius > 0) || !std::isfinite(mean_radius)) return guide;
  // The cell's side, no smaller than the grid's reach allows: +-kGridHalf cells cover the scene
  // twice over, so that a tiny target in a large scene does not send most of the scene to the
  // grid's edge cells.
  const float cell_side = std::max(kCellFraction * mean_radius, scene_reach * (2.0f / float(kGridHalf)));
  guide.inv_cell_ = 1.0f / cell_side;
  if (!std::isfinite(guide.inv_cell_)) return guide;

  // The six axes, in turn, as the normal of the point the lights are sampled from: the light
  // picker weighs lights by the cosine toward that normal, and a photon's weight divides by the
  // density it was drawn with, so any normal gives a right weight; cycling through six lets
  // every light above or below the target be found.
  static const glm::vec3 kAxes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  // Photon i of target k, its deposit (if any) appended to `out`.
  const auto trace = [&](int k, uint32_t i, std::vector<Deposit>& out) {
      const SpecularTarget target = targets[k];
      const uint64_t stream = hash_combine(0x63617573746963ull, uint64_t(k));  // "caustic"
      const PhotonNumbers u(stream, i);
      const SurfacePoint centre{target.center, glm::vec3(0.0f), kAxes[i % 6]};
      const LightSample ls = lights.sample(centre, u(0), {u(1), u(2)});
      if (!(ls.pdf > 0)) return;
      const float power = luminance(ls.radiance);
      if (!(power > 0)) return;
      Ray ray;
      float weight;
      if (std::isinf(ls.distance)) {
        // From a light at infinity: a parallel beam over the target's disc, starting on the
        // disc's plane tangent to the target on the light's side, if the light reaches it there.
        const Frame frame(ls.wi);
        const glm::vec2 disk = square_to_concentric_disk({u(3), u(4)});
        const glm::vec3 start = target.center + ls.wi * target.radius +
                                frame.to_world(glm::vec3(disk * target.radius, 0.0f));
        if (scene.occluded(start, ls.wi, std::numeric_limits<float>::infinity())) return;
        ray.o = start;
        ray.d = -ls.wi;
        // Radiance (or a directional light's irradiance) over the disc's area, per density.
        weight = power * (kPi * target.radius * target.radius) / ls.pdf;
      } else {
        // From the light's point: a direction uniform in the cone of the target's sphere.
        const glm::vec3 y = ls.point.p;
        const glm::vec3 d = target.center - y;
        const float dist2 = glm::dot(d, d);
        const float r2 = target.radius * target.radius;
        if (!(dist2 > r2)) return;
        const float inv_dist = 1.0f / std::sqrt(dist2);
        const float sin2 = std::min(r2 * (inv_dist * inv_dist), 1.0f);
        const float one_minus_cos = sin2 / (1.0f + std::sqrt(1.0f - sin2));
        const glm::vec3 dir = sample_uniform_cone(d * inv_dist, one_minus_cos, {u(3), u(4)});
        // A one-sided emitter sends nothing behind itself (point and spot lights: ng = -wi,
        // which every direction of the cone passes as the target is where wi points from).
        if (!ls.delta && glm::dot(dir, ls.point.ng) <= 0) return;
        const float solid_angle = 2.0f * kPi * one_minus_cos;
        // Power = L cos dA dw: the area density is pdf cos / distance^2, the cosines cancel.
        weight = power * solid_angle * (ls.distance * ls.distance) / ls.pdf;
        ray.o = offset_ray_origin(ls.point, dir);
        ray.d = dir;
      }
      if (!(weight > 0) || !std::isfinite(weight)) return;
      glm::vec3 beta(1.0f);
      // vertex: the specular vertices passed so far (each loop that goes on passes one).
      for (uint32_t vertex = 0;; ++vertex) {
        FacingHit f;
        if (!next_surface(scene, ray, &f)) break;
        const RenderMaterial* m = f.m;
        const SurfacePoint& sp = f.sp;
        const Hit& hit = f.hit;
        const glm::vec3 wo = f.wo;
        if (!smooth_specular(*m) || m->masked()) {
          if (vertex > 0) {
            float major;
            const float w = weight * luminance(beta);
            if (w > 0 && std::isfinite(w)) {
              out.push_back({guide.cell_key(sp.p, sp.ng), sp.p, sp.ng, uint16_t(direction_bin(wo, &major)), w});
            }
          }
          break;
        }
        if (vertex + 1 > uint32_t(kMaxSpecularVertices)) break;
        const ShadingFrame shading = shading_frame(hit, *m, scene.textures(), scene.has_uv(), wo);
        const std::optional<BsdfSample> bs = specular_sample(*m, shading.frame.to_local(wo), u(5 + vertex));
        if (!bs) break;
        const std::optional<ScatteredDirection> next = scattered_direction(shading, *bs, *m, sp);
        if (!next) break;
        beta *= bs->weight * next->perturbation;
        if (!(max_component(beta) > 0)) break;
        ray.o = offset_ray_origin(sp, next->wi);
        ray.d = next->wi;
      }
  };
  // In chunks of kChunk photons, on every thread of the caller's arena; the chunks' deposits
  // are joined in chunk order, so the same list whatever ran where.
  constexpr uint32_t kChunk = 4096;
  const uint32_t chunks_per_target = (kPhotonsPerTarget + kChunk - 1) / kChunk;
  std::vector<std::vector<Deposit>> chunks(size_t(targets.size()) * chunks_per_target);
  tbb::parallel_for(size_t(0), chunks.size(), [&](size_t c) {
    const int k = int(c / chunks_per_target);
    const uint32_t first = uint32_t(c % chunks_per_target) * kChunk;
    const uint32_t last = std::min(first + kChunk, kPhotonsPerTarget);
    for (uint32_t i = first; i < last; ++i) trace(k, i, chunks[c]);
  });
  std::vector<Deposit> deposits;
  for (const std::vector<Deposit>& chunk : chunks) deposits.insert(deposits.end(), chunk.begin(), chunk.end());
  chunks.clear();
  guide.photons_deposited_ = deposits.size();

  // The cells: deposits grouped by cell, then by bin, each group summed in photon order (a
  // stable sort keeps it), so the same bits on every machine.
  std::stable_sort(deposits.begin(), deposits.end(), [](const Deposit& a, const Deposit& b) {
    return a.key != b.key ? a.key < b.key : a.bin < b.bin;
  });
  // Each cell with enough photons: its bins' power sums (in bin order), their total, and its
  // photons' mean position and normal.
  struct Candidate {
    uint64_t key;
    Cell cell;
    std::vector<std::pair<uint16_t, float>> bins;
    float total = 0;
  };
  std::vector<Candidate> candidates;
  for (size_t begin = 0; begin < deposits.size();) {
    size_t end = begin;
    while (end < deposits.size() && deposits[end].key == deposits[begin].key) ++end;
    if (end - begin >= kMinPhotons) {
      Candidate c;
      c.key = deposits[begin].key;
      c.cell.photons = uint32_t(end - begin);
      glm::dvec3 position(0.0), normal(0.0);
      for (size_t j = begin; j < end; ++j) {
        position += glm::dvec3(deposits[j].p);
        normal += glm::dvec3(deposits[j].ng);
      }
      c.cell.position = glm::vec3(position / double(end - begin));
      c.cell.normal = glm::length(normal) > 0 ? glm::vec3(glm::normalize(normal)) : deposits[begin].ng;
      for (size_t j = begin; j < end;) {
        float sum = 0;
        size_t next = j;
        while (next < end && deposits[next].bin == deposits[j].bin) sum += deposits[next++].weight;
        c.bins.emplace_back(deposits[j].bin, sum);
        c.total += sum;
        j = next;
      }
      candidates.push_back(std::move(c));
    }
    begin = end;
  }
  deposits.clear();

  // Each cell's probability of a guided bounce: E_c from its photons (each target's photons
  // estimate the power into it, as the mean of their weights; the cell's area taken as a grid
  // square), E_i by one bounce from the cell's mean position. Only the cells kept get bins.
  const float power_to_irradiance = 1.0f / (float(kPhotonsPerTarget) * cell_side * cell_side);
  std::vector<float> indirect(candidates.size());
  tbb::parallel_for(size_t(0), indirect.size(), [&](size_t c) {
    indirect[c] = indirect_irradiance(scene, candidates[c].cell.position, candidates[c].cell.normal, candidates[c].key);
  });
  std::vector<uint64_t> cell_keys;
  for (size_t c = 0; c < candidates.size(); ++c) {
    Candidate& candidate = candidates[c];
    const float e_caustic = candidate.total * power_to_irradiance;
    const float p = e_caustic / (e_caustic + indirect[c]);
    if (!(p >= kMinProbability)) continue;
    Cell& cell = candidate.cell;
    cell.probability = std::min(p, kMaxProbability);
    cell.first = uint32_t(guide.bin_ids_.size());
    cell.count = uint32_t(candidate.bins.size());
    float cdf = 0;
    for (const auto& [bin, sum] : candidate.bins) {
      guide.bin_ids_.push_back(bin);
      guide.prob_.push_back(sum / candidate.total);
      cdf += guide.prob_.back();
      guide.cdf_.push_back(cdf);
    }
    guide.cdf_.back() = 1.0f;
    guide.cells_.push_back(cell);
    cell_keys.push_back(candidate.key);
    guide.photons_kept_ += cell.photons;
  }

  // The table from cell keys to cells: open addressing, at most half full.
  size_t capacity = 16;
  while (capacity < 2 * cell_keys.size()) capacity *= 2;
  guide.mask_ = capacity - 1;
  guide.keys_.assign(capacity, kEmptyKey);
  guide.slot_cell_.assign(capacity, -1);
  for (size_t c = 0; c < cell_keys.size(); ++c) {
    uint64_t s = mix64(cell_keys[c]) & guide.mask_;
    while (guide.keys_[s] != kEmptyKey) s = (s + 1) & guide.mask_;
    guide.keys_[s] = cell_keys[c];
    guide.slot_cell_[s] = int32_t(c);
  }
  return guide;
}

}  // namespace tessera
