// The parts of a path vertex that other passes over the scene share with it: the shading frame
// and the facing material at a hit, the light term and its MIS weight, the (guided) BSDF bounce,
// the smooth specular sample, the shadow ray toward a light sample. path_vertex.h strings them
// into one vertex; the caustic guide's photons (caustic_photons.cpp) pass glass and mirrors with
// the same functions, so a photon bends where a path does, bit for bit.
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>

#include <glm/geometric.hpp>

#include "render/bsdf/bsdf.h"
#include "render/guiding/caustic_guide.h"
#include "render/integrators/path_state.h"
#include "render/math/frame.h"
#include "render/scene/traceable_scene.h"
#include "render/texture/shading_normal.h"
#include "render/texture/texture_set.h"

namespace tessera {
namespace path_vertex_detail {

/// Where the hit's material looks up its textures (mesh attributes from the shape hit, volume
/// textures at the world position).
inline TexturePoint texture_point(const Hit& hit) {
  return {hit.uv, hit.geometry ? &hit.geometry->attributes : nullptr, hit.primitive,
          hit.barycentric, hit.sp.p};
}

/// Dimension pairs per path vertex: (light choice, roulette), light point, BSDF direction,
/// (BSDF lobe, mask). Pair 0 is an independent hash; pair 3 is a Sobol pair like 1 and 2: a
/// smooth dielectric's reflect-or-refract choice is its only random decision, and drawn from
/// an independent hash it raised cornell-sphere's 64-spp RMSE by 8 % (0.0410 -> 0.0438, seeds
/// 0-2; docs/renderer.md, "BSDFs").
constexpr uint32_t kPairsPerVertex = 4;
constexpr float kMaxSurvival = 0.95f;
/// Roulette spares this many consecutive delta vertices (mirror, smooth glass): a specular
/// vertex does not branch, and light through glass onto a diffuse point (the caustic paths,
/// about three quarters of cornell-sphere's and hexroom's variance) was rouletted at the glass
/// with survival of about the diffuse albedo, which multiplied those rare, bright samples by
/// 1 / albedo. Past this many in a row roulette applies again, so a path trapped by total
/// internal reflection (throughput 1) still ends. Measured: docs/renderer.md, "Light
/// transport" (where the glass scenes' error lives).
constexpr int kFreeSpecularVertices = 4;

inline float max_component(glm::vec3 v) { return std::max(v.x, std::max(v.y, v.z)); }

/// The power heuristic (exponent 2), as Mitsuba's path tracer weighs its two strategies.
inline float mis_weight(float pdf_a, float pdf_b) {
  const float a = pdf_a * pdf_a, b = pdf_b * pdf_b;
  const float w = a / (a + b);
  return std::isfinite(w) ? w : 0.0f;
}

/// Where a shadow ray towards a point, spot or projector light ends, as a fraction of the way:
/// Mitsuba's `Interaction::spawn_ray_to` ends every shadow ray at (1 - ShadowEpsilon) of the
/// distance, ShadowEpsilon = 15000 * 2^-24. A delta light has no surface whose error bound could
/// tell where it ends, and scenes put such lights on a surface (a spot on the floor, pointing
/// up: langevin-mc-rendering's scene_directional.xml): ending at the light itself, the shadow
/// ray would hit that surface at the light's own position and leave the scene black, where
/// Mitsuba lights it.
inline constexpr float kDeltaShadowEnd = 1.0f - 15000.0f * 0x1p-24f;

/// Sets `q` to the shadow ray of light sample `ls` from `origin` (already offset off the
/// surface): to the light's offset point (area lights), short of the light's position by
/// kDeltaShadowEnd (point, spot, projector), or unbounded for lights at infinity.
inline void set_shadow_ray(glm::vec3 origin, const LightSample& ls, ShadowQuery* q) {
  q->o = origin;
  if (std::isinf(ls.distance)) {
    q->d = ls.wi;
    q->t_max = std::numeric_limits<float>::infinity();
  } else {
    const glm::vec3 to = offset_ray_origin(ls.point, -ls.wi);
    q->d = to - origin;
    q->t_max = ls.delta ? kDeltaShadowEnd : 1.0f;
  }
}

/// The shading frame at a hit: the interpolated normal, perturbed by a normal or bump map as
/// Mitsuba's adapters do (texture/shading_normal.h), with its tangent along dpdu when the scene
/// has uvs (anisotropic roughness is measured there). `wo` points to the previous vertex.
struct ShadingFrame {
  Frame frame;
  glm::vec3 ns;            ///< the unperturbed shading normal
  bool perturbed = false;  ///< a normal or bump map moved the normal
};

inline ShadingFrame shading_frame(const Hit& hit, const RenderMaterial& m, const TextureSet& textures,
                           bool has_uv, glm::vec3 wo) {
  ShadingFrame out{Frame(hit.ns), hit.ns, false};
  glm::vec3 n = hit.ns;
  if (m.normal_map >= 0) {
    n = normal_mapped(textures.lookup(m.normal_map, hit.uv), hit.dpdu, hit.dpdv, hit.ns, wo);
    out.perturbed = true;
  } else if (m.bump_map >= 0) {
    n = bump_mapped(textures.gradient(m.bump_map, hit.uv), m.bump_scale, hit.dpdu, hit.dpdv,
                    hit.ns, hit.sp.ng, wo);
    out.perturbed = true;
  }
  if (!std::isfinite(n.x + n.y + n.z) || !(glm::dot(n, n) > 0)) {
    n = hit.ns;
    out.perturbed = false;
  }
  if (!has_uv && !out.perturbed) return out;
  const glm::vec3 s = out.perturbed ? perturbed_tangent(n, shading_tangent(hit.dpdu, hit.ns))
                                    : shading_tangent(hit.dpdu, n);
  out.frame.n = n;
  out.frame.s = s;
  out.frame.t = glm::cross(n, s);
  return out;
}

/// The factor a perturbed normal puts on a BSDF value towards wi (Mitsuba's adapters): 0 when
/// wi lies on different sides of the perturbed and the true shading normal, else the
/// shadow-terminator softening.
inline float perturbation_factor(const ShadingFrame& f, glm::vec3 wi) {
  if (!f.perturbed) return 1.0f;
  if (glm::dot(wi, f.ns) * glm::dot(wi, f.frame.n) <= 0) return 0.0f;
  return shadow_terminator(f.frame.n, f.ns, wi);
}

/// A masked material's opacity at the hit (Mitsuba's mask: its constant times its texture,
/// clamped to [0, 1]); 1 for a material without a mask.
inline float opacity_at(const RenderMaterial& m, const TextureSet& textures, const Hit& hit) {
  if (!m.masked()) return 1.0f;
  return m.opacity.texture < 0
             ? m.opacity.value
             : std::clamp(m.opacity.value * textures.lookup_1(m.opacity.texture, texture_point(hit)), 0.0f, 1.0f);
}

/// The MIS weight of emission that the last bounce found at `hit` (an area emitter): 1 after a
/// delta lobe or where no light sample was taken (`prev_delta`), else the power heuristic of the
/// bounce's density `prev_pdf` against the light sampler's density of that point.
inline float emitter_hit_weight(const LightSet& lights, bool prev_delta, float prev_pdf, const SurfacePoint& prev_sp,
                                const Hit& hit) {
  return prev_delta ? 1.0f
                    : mis_weight(prev_pdf, lights.pdf_area(*hit.geometry, hit.primitive, prev_sp, hit.sp.p, hit.sp.ng));
}

/// The same for the environment, reached by an escaping ray along d.
inline float environment_weight(const LightSet& lights, bool prev_delta, float prev_pdf, const SurfacePoint& prev_sp,
                                glm::vec3 d) {
  return prev_delta ? 1.0f : mis_weight(prev_pdf, lights.pdf_environment(prev_sp, d));
}

/// The material that shades a hit seen from `wo`, with `sp` and `hit` turned to face `wo`: a
/// surface other than a dielectric seen from behind takes its back material (Mitsuba's
/// twosided with two BSDFs) or, two-sided, its front one; a one-sided surface is black from
/// behind (nullptr). A dielectric keeps its orientation (its inside is a side of its own).
inline const RenderMaterial* facing_material(const TraceableScene& scene, const RenderMaterial* m, glm::vec3 wo,
                                             SurfacePoint& sp, Hit& hit) {
  if (glm::dot(wo, sp.ng) > 0 || m->dielectric()) return m;
  if (m->back >= 0) {
    m = &scene.material(uint32_t(m->back));
  } else if (!m->two_sided) {
    return nullptr;
  }
  sp.ng = -sp.ng;
  hit.ns = -hit.ns;
  return m;
}

/// What a light sample gives a vertex shaded by a general Bsdf: the BSDF's value toward it
/// (with the perturbed normal's factor) and its MIS weight against the BSDF's own sampling,
/// whose density counts the mask's `opacity` (see path_vertex). nullopt when the sample cannot
/// contribute: no density or radiance, a zero value, or a reflection toward below the
/// geometric surface (light must leave a reflecting surface on the side it arrived from).
struct LightTerm {
  glm::vec3 f;
  float w;
};
/// `guide`, `at`: the caustic guide and its cell at the vertex when the bounce follows it too
/// (see guided_bsdf_sample), else at.cell = -1.
inline std::optional<LightTerm> light_term(const Bsdf& bsdf, const ShadingFrame& shading, glm::vec3 wo_local,
                                           const LightSample& ls, const RenderMaterial& m, const SurfacePoint& sp,
                                           float opacity, const CausticGuide* guide = nullptr,
                                           CausticGuide::At at = {}) {
  if (!(ls.pdf > 0) || ls.radiance == glm::vec3(0.0f)) return std::nullopt;
  const glm::vec3 wi_local = shading.frame.to_local(ls.wi);
  const glm::vec3 f = bsdf.eval(wo_local, wi_local) * perturbation_factor(shading, ls.wi);
  const bool leaks = !m.dielectric() && glm::dot(sp.ng, ls.wi) <= 0;
  if (f == glm::vec3(0.0f) || leaks) return std::nullopt;
  if (ls.delta) return LightTerm{f, 1.0f};
  const float bsdf_pdf = bsdf.pdf(wo_local, wi_local);
  const float pdf = at.cell < 0 ? bsdf_pdf : guide->mixed_pdf(at, bsdf_pdf, ls.wi);
  return LightTerm{f, mis_weight(ls.pdf, pdf * opacity)};
}

/// The bounce of a general Bsdf at a vertex in the caustic guide's cell `at.cell` (taken with
/// probability p = at.probability, caustic_guide.h): below p, u_lobe (rescaled) picks the
/// guide's bin and u_bsdf the direction in it, f |cos| from bsdf.eval; above, bsdf.sample with
/// u_lobe rescaled. A non-delta sample's weight and pdf are those of the one-sample mixture,
/// (1 - p) bsdf.pdf + p guide.pdf; a delta lobe's pdf and weight count the (1 - p) share of
/// choosing the BSDF. *bsdf_pdf receives bsdf.pdf of the direction (for the roulette, which
/// weighs the throughput as the BSDF's own sample would have left it).
inline std::optional<BsdfSample> guided_bsdf_sample(const Bsdf& bsdf, const Frame& frame, glm::vec3 wo_local,
                                                    float u_lobe, glm::vec2 u_bsdf, const CausticGuide& guide,
                                                    CausticGuide::At at, float* bsdf_pdf) {
  const float guided = at.probability;
  if (u_lobe < guided) {
    int bin = -1;
    const glm::vec3 wi = guide.sample(at.cell, u_lobe / guided, u_bsdf, &bin);
    BsdfSample s;
    s.wi = frame.to_local(wi);
    const glm::vec3 f = bsdf.eval(wo_local, s.wi);
    *bsdf_pdf = bsdf.pdf(wo_local, s.wi);
    s.pdf = guide.mixed_pdf(at, *bsdf_pdf, wi, bin);
    if (!(s.pdf > 0) || f == glm::vec3(0.0f)) return std::nullopt;
    s.weight = f / s.pdf;
    return s;
  }
  std::optional<BsdfSample> s = bsdf.sample(wo_local, CausticGuide::other_strategy(u_lobe, guided), u_bsdf);
  if (!s) return s;
  *bsdf_pdf = s->pdf;
  if (s->delta) {
    s->weight /= 1.0f - guided;
    s->pdf *= 1.0f - guided;
    return s;
  }
  const float pdf = guide.mixed_pdf(at, s->pdf, frame.to_world(s->wi));
  s->weight *= s->pdf / pdf;
  s->pdf = pdf;
  return s;
}

/// Whether a vertex shaded by the general Bsdf of `m` follows the caustic guide too: the
/// diffuse materials (textured, or with a normal or bump map), whose bounce gathers light from
/// the whole hemisphere as the untextured diffuse vertex's does, the plastics and principled
/// surfaces, whose diffuse lobe does, and rough conductors, whose lobe can be broad enough to
/// gather a caustic (the guided share scaled by Bsdf::caustic_guide_share: the diffuse lobe's
/// probability, or min(1, 2 alpha); the other lobes are left to the BSDF).
inline bool guided_material(const RenderMaterial& m) {
  return m.type == MaterialType::diffuse || m.type == MaterialType::plastic ||
         m.type == MaterialType::rough_plastic || m.type == MaterialType::principled ||
         m.type == MaterialType::rough_conductor;
}

/// The unit world direction of BSDF sample `bs` and the perturbed normal's factor on its
/// weight; nullopt when the path ends there: a degenerate direction, a reflection below the
/// geometric surface, or a direction the perturbed normal's factor zeroes.
struct ScatteredDirection {
  glm::vec3 wi;
  float perturbation;
};
inline std::optional<ScatteredDirection> scattered_direction(const ShadingFrame& shading, const BsdfSample& bs,
                                                             const RenderMaterial& m, const SurfacePoint& sp) {
  glm::vec3 wi = shading.frame.to_world(bs.wi);
  const float len2 = glm::dot(wi, wi);
  if (!(len2 > 0)) return std::nullopt;
  wi /= std::sqrt(len2);
  if (!m.dielectric() && glm::dot(wi, sp.ng) <= 0) return std::nullopt;
  const float perturbation = perturbation_factor(shading, wi);
  if (!(perturbation > 0)) return std::nullopt;
  return ScatteredDirection{wi, perturbation};
}

/// Whether `m` is smooth glass, a mirror or a smooth conductor with constant parameters: only
/// delta lobes (no light sample, no MIS), sampled by specular_sample without the general Bsdf.
inline bool smooth_specular(const RenderMaterial& m) {
  return !m.textured &&
         (m.type == MaterialType::glass || m.type == MaterialType::mirror || m.type == MaterialType::conductor);
}

/// Bsdf(bsdf_params(m, ...)).sample(wo, u_lobe, u) for a material smooth_specular accepts, bit
/// for bit: the BSDF built from the material's constants as bsdf_params would pass them
/// (material.cpp), and Bsdf::sample's check of the result (bsdf.cpp). The general path built a
/// BsdfParams (every material's fields) and a variant per glass or mirror vertex: about 360
/// instructions of the vertex (BENCHMARKS.md, "Instructions per sample").
inline std::optional<BsdfSample> specular_sample(const RenderMaterial& m, glm::vec3 wo, float u_lobe) {
  return checked_sample(
      m.type == MaterialType::glass
          ? DielectricBsdf(m.ior, m.specular_reflectance.value, m.specular_transmittance.value)
                .sample(wo, u_lobe, glm::vec2(0.0f))
          : ConductorBsdf(m.specular_reflectance.value, m.conductor_eta, m.conductor_k,
                          m.perfect || m.type == MaterialType::mirror)
                .sample(wo, u_lobe, glm::vec2(0.0f)));
}

}  // namespace path_vertex_detail

}  // namespace tessera
