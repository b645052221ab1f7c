// One vertex of the path tracer (path_vertex()), defined here so that both integrators inline
// it: the scalar trace_path() (integrator.cpp) and the wavefront integrator
// (wavefront/wavefront_integrator.h). Both call the same function, so a path's arithmetic and
// sampler calls are the same in both and so are its bits. The shading parts it strings together
// are in vertex_shading.h.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include <glm/geometric.hpp>

#include "render/guiding/target_mixture.h"
#include "render/integrators/integrator.h"
#include "render/integrators/vertex_shading.h"
#include "render/sampling/warp.h"

namespace tessera {

/// Dimension pairs pair + 1 (the light point) and pair + 2 (the BSDF direction) of a vertex
/// whose pairs are Sobol pairs, drawn ahead for many paths at once (the wavefront kernels,
/// wavefront/wavefront_kernel.inc): exactly what PixelSampler::get2d returns for them.
/// `bsdf_cosine` is square_to_cosine_hemisphere(bsdf) (warp.h), computed lane-wise with the
/// same operations in the same order (wavefront_kernel.inc's cosine_lanes): a diffuse vertex
/// takes it instead of warping the pair itself.
struct PredrawnPairs {
  glm::vec2 light;
  glm::vec2 bsdf;
  glm::vec3 bsdf_cosine;
};

/// TargetMixture::init or a function giving the same bits (path_vertex's `init_mixture`).
using MixtureInit = bool (*)(TargetMixture& mix, const SpecularTargets& targets, glm::vec3 p, glm::vec3 n);

namespace path_vertex_detail {
/// Dimension pair `pair` of the path's sampler, or `*predrawn` when the kernel drew it ahead
/// (the same numbers: PredrawnPairs); the sampler is not asked then.
inline glm::vec2 pair_or_predrawn(PixelSampler& sampler, uint32_t pair, const glm::vec2* predrawn) {
  if (predrawn) return *predrawn;
  sampler.set_pair(pair);
  return sampler.get2d();
}
}  // namespace path_vertex_detail

namespace path_vertex_detail {

/// What the parts of one vertex share: the scene, the path and its sampler, where the shadow
/// query goes, the numbers the caller drew or worked out ahead (path_vertex's `predrawn`,
/// `init_mixture`, `light_importance`), the vertex's first dimension pair, and whether
/// roulette applies at it.
struct VertexContext {
  const TraceableScene& scene;
  PixelSampler& sampler;
  PathState& path;
  ShadowQuery* shadow;
  bool* has_shadow;
  const PredrawnPairs* predrawn;
  MixtureInit init_mixture;
  const PointImportance* light_importance;
  uint32_t pair;
  bool roulette;
  bool have_lights;
};

/// How a surface vertex scattered: the numbers of its pair 0 (x chose the light, y decides
/// roulette; zero when not drawn), the new direction, its solid-angle density as the next
/// vertex's MIS sees it, and whether it came from a delta lobe.
struct Scatter {
  glm::vec2 u_choice{0.0f};
  glm::vec3 wi;
  float bsdf_pdf = 0;
  bool delta = false;
};

/// An escaped ray: the environment's light, weighed against the BSDF sample that aimed it.
[[gnu::always_inline]] inline void add_environment(const TraceableScene& scene, PathState& path) {
  const LightSet& lights = scene.lights();
  if (lights.has_environment() && !(path.vertex == 0 && scene.hide_emitters())) {
    const glm::vec3 le = lights.environment(path.ray.d);
    const float w = environment_weight(lights, path.prev_delta, path.prev_pdf, path.prev_sp, path.ray.d);
    path.radiance += glm::dvec3(path.beta) * glm::dvec3(le) * double(w);
  }
}

/// The light of the emitter `hit` lies on, seen from `wo`, weighed against the BSDF sample
/// that found it.
[[gnu::always_inline]] inline void add_emission(const TraceableScene& scene, PathState& path, const Hit& hit,
                                                glm::vec3 wo) {
  const LightSet& lights = scene.lights();
  const glm::vec3 le = lights.emitted(*hit.geometry, hit.primitive, hit.uv, hit.sp.ng, wo);
  if (le != glm::vec3(0.0f)) {
    const float w = emitter_hit_weight(lights, path.prev_delta, path.prev_pdf, path.prev_sp, hit);
    path.radiance += glm::dvec3(path.beta) * glm::dvec3(le) * double(w);
  }
}

/// The ray goes straight on through `hit`, from just past it.
[[gnu::always_inline]] inline void pass_through(Ray& ray, const Hit& hit) {
  ray.o = offset_ray_origin(hit.sp, ray.d);
  ray.t_max = std::numeric_limits<float>::infinity();
}

/// A masked surface's null interaction: the path goes straight on (a vertex all the same, as
/// in Mitsuba), after roulette where it applies. False when roulette ends the path.
[[gnu::always_inline]] inline bool null_scatter(const VertexContext& c, const Hit& hit) {
  PathState& path = c.path;
  if (c.roulette) {
    c.sampler.set_pair(c.pair);
    const float survival = std::min(max_component(path.beta) * path.eta_scale, kMaxSurvival);
    if (c.sampler.get2d_independent().y >= survival) return false;
    path.beta /= survival;
  }
  path.prev_delta = true;
  path.prev_sp = hit.sp;
  pass_through(path.ray, hit);
  ++path.vertex;
  return true;
}

/// Next-event estimation at an untextured diffuse vertex: one light sample, its shadow ray from
/// `origin`, weighed against the bounce's density toward it (the caustic guide's and the
/// target mixture's when they have a say here).
[[gnu::always_inline]] inline void diffuse_light_sample(const VertexContext& c, const RenderMaterial& m,
                                                        const SurfacePoint& sp, glm::vec3 ns, glm::vec3 origin,
                                                        float opacity, const TargetMixture& mix, bool mixture,
                                                        const CausticGuide::At& guided, glm::vec2 u_choice) {
  const CausticGuide& guide = c.scene.caustic_guide();
  const glm::vec2 u_light = pair_or_predrawn(c.sampler, c.pair + 1, c.predrawn ? &c.predrawn->light : nullptr);
  const LightSample ls = c.scene.lights().sample(sp, u_choice.x, u_light, c.light_importance);
  if (ls.pdf > 0) {
    const float cos_surface = glm::dot(ns, ls.wi);
    if (cos_surface > 0 && glm::dot(sp.ng, ls.wi) > 0 && ls.radiance != glm::vec3(0.0f)) {
      // The bounce's density toward ls.wi: the mixture's when it has cones here.
      const float w =
          ls.delta            ? 1.0f
          : guided.cell >= 0 ? mis_weight(ls.pdf, guide.mixed_pdf(guided,
                                                                  mixture ? mix.pdf(ls.wi, cos_surface)
                                                                          : cos_surface * kInvPi,
                                                                  ls.wi) *
                                                      opacity)
          : mixture          ? mis_weight(ls.pdf, mix.pdf(ls.wi, cos_surface) * opacity)
                             : mis_weight(ls.pdf, cos_surface * (opacity * kInvPi));
      set_shadow_ray(origin, ls, c.shadow);
      // (albedo / pi) cos Le / pdf, in double so tiny, bright lights cannot overflow.
      c.shadow->contribution = glm::dvec3(c.path.beta) * glm::dvec3(m.albedo) * glm::dvec3(ls.radiance) *
                               (double(cos_surface) * double(kInvPi) * double(w) / double(ls.pdf));
      *c.has_shadow = true;
    }
  }
}

/// The bounce of an untextured diffuse vertex: the cosine-weighted direction, or, where the
/// target mixture or the caustic guide has a say, one of their strategies chosen by pair + 3's
/// x. Updates the throughput; false when the direction falls below the surface.
[[gnu::always_inline]] inline bool diffuse_bounce(const VertexContext& c, const RenderMaterial& m,
                                                  const SurfacePoint& sp, glm::vec3 ns, float opacity,
                                                  TargetMixture& mix, bool mixture, const CausticGuide::At& guided,
                                                  Scatter* s) {
  PathState& path = c.path;
  const CausticGuide& guide = c.scene.caustic_guide();
  const glm::vec2 u_bsdf = pair_or_predrawn(c.sampler, c.pair + 2, c.predrawn ? &c.predrawn->bsdf : nullptr);
  if (!mixture && guided.cell < 0) {
    // The cosine-weighted direction in the normal's frame, warped lane-wise with the pair when
    // the kernel drew it.
    const glm::vec3 local = c.predrawn ? c.predrawn->bsdf_cosine : square_to_cosine_hemisphere(u_bsdf);
    s->wi = Frame(ns).to_world(local);
    if (glm::dot(s->wi, sp.ng) <= 0) return false;
    path.beta *= m.albedo;  // f * cos / pdf = (albedo / pi) * cos / (cos / pi)
    s->bsdf_pdf = local.z * kInvPi * opacity;
    return true;
  }
  // The strategy from pair + 3's x, which this path leaves free (a mask takes its y): the
  // guide below the cell's probability (the number over it picks the bin), else the mixture
  // (or the cosine where there are no cones) with the rest rescaled.
  c.sampler.set_pair(c.pair + 3);
  float u_strategy = c.sampler.get2d_x();
  int bin = -1, cone = -1;
  if (guided.cell >= 0) {
    if (u_strategy < guided.probability) {
      s->wi = guide.sample(guided.cell, u_strategy / guided.probability, u_bsdf, &bin);
    } else {
      u_strategy = CausticGuide::other_strategy(u_strategy, guided.probability);
    }
  }
  if (bin < 0) {
    cone = mixture ? mix.choose(u_strategy) : -1;
    s->wi = cone >= 0    ? mix.sample_cone(cone, u_bsdf)
            : c.predrawn ? Frame(ns).to_world(c.predrawn->bsdf_cosine)
                         : Frame(ns).to_world(square_to_cosine_hemisphere(u_bsdf));
  }
  const float cos_n = glm::dot(s->wi, ns);
  if (!(cos_n > 0) || glm::dot(s->wi, sp.ng) <= 0) return false;
  const float unguided = mixture ? mix.pdf(s->wi, cos_n, cone) : cos_n * kInvPi;
  const float pdf = guided.cell < 0 ? unguided : guide.mixed_pdf(guided, unguided, s->wi, bin);
  path.beta *= m.albedo * (cos_n * kInvPi / pdf);  // f cos / pdf_mix, f = albedo / pi
  s->bsdf_pdf = pdf * opacity;
  // Russian roulette weighs the throughput as the cosine sample would have left it: a
  // bounce toward a target carries a small beta by design, and ending it for that would
  // undo what aiming it gained (measured: docs/renderer.md).
  path.eta_scale *= pdf / (cos_n * kInvPi);
  return true;
}

/// The common case, with nothing of the other materials in its way: a Lambertian surface of
/// constant albedo. Both the shadow ray and the bounce leave on the front side. False when the
/// path ends here.
[[gnu::always_inline]] inline bool diffuse_vertex(const VertexContext& c, const RenderMaterial& m, const Hit& hit,
                                                  const SurfacePoint& sp, float opacity, Scatter* s) {
  const TraceableScene& scene = c.scene;
  const glm::vec3 ns = hit.ns;
  const glm::vec3 origin = offset_ray_origin(sp, sp.ng);
  // Bounces toward the scene's glass and mirrors (specular_targets.h): a scene without them
  // pays this one branch.
  TargetMixture mix;
  const bool mixture = !scene.specular_targets().empty() &&
                       (c.init_mixture ? c.init_mixture(mix, scene.specular_targets(), sp.p, ns)
                                       : mix.init(scene.specular_targets(), sp.p, ns));
  // Bounces along the caustics (caustic_guide.h): with the cell's probability where the guide
  // has a cell, the rest as above. A scene without one pays the empty() test.
  const CausticGuide::At guided = scene.caustic_guide().at(sp.p, sp.ng);
  if (c.roulette || c.have_lights) {
    c.sampler.set_pair(c.pair);
    s->u_choice = c.sampler.get2d_independent();
  }
  if (c.have_lights) diffuse_light_sample(c, m, sp, ns, origin, opacity, mix, mixture, guided, s->u_choice);
  if (!diffuse_bounce(c, m, sp, ns, opacity, mix, mixture, guided, s)) return false;
  c.path.ray.o = origin;
  return true;
}

/// A general BSDF's light sample and direction (any material but smooth specular ones and
/// untextured diffuse ones), with the caustic guide where the material follows it. Empty when
/// the BSDF gives no direction.
[[gnu::always_inline]] inline std::optional<BsdfSample> bsdf_sample_vertex(const VertexContext& c,
                                                                           const RenderMaterial& m, const Hit& hit,
                                                                           const SurfacePoint& sp,
                                                                           const ShadingFrame& shading,
                                                                           glm::vec3 wo_local, float opacity,
                                                                           glm::vec2* u_choice) {
  const Bsdf bsdf(bsdf_params(m, c.scene.textures(), texture_point(hit)));
  // The caustic guide, as at an untextured diffuse vertex (diffuse_vertex), for the materials
  // that follow it.
  const CausticGuide& guide = c.scene.caustic_guide();
  CausticGuide::At guided = guided_material(m) ? guide.at(sp.p, sp.ng) : CausticGuide::At{};
  if (guided.cell >= 0 && m.type != MaterialType::diffuse) {
    // The guide serves a plastic's or a principled surface's diffuse lobe, or a rough
    // conductor's broad one: its share scaled (the same At for the light sample's MIS and
    // the bounce, so any share is unbiased).
    guided.probability *= bsdf.caustic_guide_share(wo_local);
    if (!(guided.probability > 0)) guided = CausticGuide::At{};
  }
  if (c.roulette || (c.have_lights && bsdf.has_smooth_lobe())) {
    c.sampler.set_pair(c.pair);
    *u_choice = c.sampler.get2d_independent();
  }
  if (c.have_lights && bsdf.has_smooth_lobe()) {
    const glm::vec2 u_light = pair_or_predrawn(c.sampler, c.pair + 1, c.predrawn ? &c.predrawn->light : nullptr);
    const LightSample ls = c.scene.lights().sample(sp, u_choice->x, u_light, c.light_importance);
    if (const std::optional<LightTerm> lt = light_term(bsdf, shading, wo_local, ls, m, sp, opacity, &guide, guided)) {
      set_shadow_ray(offset_ray_origin(sp, ls.wi), ls, c.shadow);
      c.shadow->contribution = glm::dvec3(c.path.beta) * glm::dvec3(lt->f) * glm::dvec3(ls.radiance) *
                               (double(lt->w) / double(ls.pdf));
      *c.has_shadow = true;
    }
  }
  c.sampler.set_pair(c.pair + 3);
  const float u_lobe = c.sampler.get2d_x();
  const glm::vec2 u_bsdf = pair_or_predrawn(c.sampler, c.pair + 2, c.predrawn ? &c.predrawn->bsdf : nullptr);
  if (guided.cell < 0) return bsdf.sample(wo_local, u_lobe, u_bsdf);
  float unguided_pdf = 0;
  const std::optional<BsdfSample> bs =
      guided_bsdf_sample(bsdf, shading.frame, wo_local, u_lobe, u_bsdf, guide, guided, &unguided_pdf);
  // Roulette weighs the throughput as the BSDF's own sample would have left it (as at an
  // untextured diffuse vertex).
  if (bs && !bs->delta && unguided_pdf > 0) c.path.eta_scale *= bs->pdf / unguided_pdf;
  return bs;
}

/// Every material but an untextured diffuse one: the shading frame, a smooth specular lobe
/// drawn directly or a general BSDF's light sample and direction, then the direction through
/// the shading normal. False when the path ends here.
[[gnu::always_inline]] inline bool bsdf_vertex(const VertexContext& c, const RenderMaterial& m, const Hit& hit,
                                               const SurfacePoint& sp, glm::vec3 wo, float opacity, Scatter* s) {
  PathState& path = c.path;
  const ShadingFrame shading = shading_frame(hit, m, c.scene.textures(), c.scene.has_uv(), wo);
  const glm::vec3 wo_local = shading.frame.to_local(wo);
  std::optional<BsdfSample> bs;
  if (smooth_specular(m)) {
    // Delta lobes only: no light sample; the lobe choice from pair + 3's x, as for the general
    // BSDFs (the direction pair is not drawn: these BSDFs ignore it, and every draw sets its
    // pair).
    if (c.roulette) {
      c.sampler.set_pair(c.pair);
      s->u_choice = c.sampler.get2d_independent();
    }
    c.sampler.set_pair(c.pair + 3);
    bs = specular_sample(m, wo_local, c.sampler.get2d_x());
  } else {
    bs = bsdf_sample_vertex(c, m, hit, sp, shading, wo_local, opacity, &s->u_choice);
  }
  if (!bs) return false;
  const std::optional<ScatteredDirection> out = scattered_direction(shading, *bs, m, sp);
  if (!out) return false;
  s->wi = out->wi;
  path.beta *= bs->weight * out->perturbation;
  s->bsdf_pdf = bs->pdf * opacity;
  s->delta = bs->delta;
  path.eta_scale *= bs->eta * bs->eta;
  path.ray.o = offset_ray_origin(sp, s->wi);
  return true;
}

/// After a surface scattered: roulette where it applies (sparing the first
/// kFreeSpecularVertices delta vertices in a row), then the next ray along `s.wi` from
/// path.ray.o. False when the path ends here.
[[gnu::always_inline]] inline bool next_ray(PathState& path, const Scatter& s, const SurfacePoint& sp,
                                            bool roulette) {
  if (!(max_component(path.beta) > 0)) return false;
  path.specular_run = s.delta ? path.specular_run + 1 : 0;
  if (roulette && !(s.delta && path.specular_run <= kFreeSpecularVertices)) {
    const float survival = std::min(max_component(path.beta) * path.eta_scale, kMaxSurvival);
    if (s.u_choice.y >= survival) return false;
    path.beta /= survival;
  }
  path.prev_delta = s.delta;
  path.prev_pdf = s.bsdf_pdf;
  path.prev_sp = sp;
  path.ray.d = s.wi;
  path.ray.t_max = std::numeric_limits<float>::infinity();
  ++path.vertex;
  return true;
}

}  // namespace path_vertex_detail

/// Shades the vertex of `path` that its ray found: `hit` is the closest hit of path.ray
/// (TraceableScene::intersect, or the same Hit built from a packet query), nullptr when the ray
/// escaped; it may be changed (a back face flips its normals).
///
/// Adds what the vertex sees directly to path.radiance; asks for at most one shadow ray, in
/// `*shadow`, returning `*has_shadow` (the caller traces it and adds its contribution when
/// unblocked); then either samples the next direction, leaving the next ray in path.ray, and
/// returns true, or returns false when the path ends (escaped, absorbed, roulette, depth).
/// `sampler` is the path's own (pixel, sample index) stream; every dimension is set by pair
/// index, so a vertex draws the same numbers whatever ran before it.
///
/// Lambertian surfaces get next-event estimation (one emitter chosen by power, one point on it
/// by area, one shadow ray) plus a cosine-weighted bounce; other BSDFs combine both strategies
/// by multiple importance sampling. Russian roulette from the scene's rr_depth-th vertex on
/// (vertex + 1 >= rr_depth, as Mitsuba's path integrator counts; the third by default),
/// survival min(max(beta * eta^2), 0.95), except at the first kFreeSpecularVertices delta
/// vertices in a row: unbiased, and a path trapped by total internal reflection still ends.
/// `max_depth`
/// follows Mitsuba (path segments including the camera ray; -1 = unbounded).
///
/// Inlined into both integrators' loops (trace_path in integrator.cpp, the wavefront's lane
/// loop), so that the shadow query and the locals stay in registers: called out of line it
/// cost trace_path 2.4 % more instructions per sample.
///
/// `predrawn`, when given, holds the vertex's pairs pair + 1 and pair + 2 (the same numbers the
/// sampler would give), and the sampler is not asked for them.
///
/// `init_mixture`, when given, builds the bounce mixture in place of TargetMixture::init (the
/// same bits): the wavefront kernels pass their own, built for their instruction set with
/// eight targets per operation (wavefront_kernel.inc).
///
/// `light_importance`, when given, holds every light's importance at the hit (the same bits
/// as the light picker's own evaluation): the wavefront kernels work it out for a packet's
/// lanes at once.
[[gnu::always_inline]] inline bool path_vertex(const TraceableScene& scene, int max_depth, PixelSampler& sampler,
                                               PathState& path, Hit* hit, ShadowQuery* shadow, bool* has_shadow,
                                               const PredrawnPairs* predrawn = nullptr,
                                               MixtureInit init_mixture = nullptr,
                                               const PointImportance* light_importance = nullptr) {
  using namespace path_vertex_detail;
  const int vertex = path.vertex;
  *has_shadow = false;
  if (!hit) {
    add_environment(scene, path);
    return false;
  }
  const glm::vec3 wo = -path.ray.d;  // every ray the integrator spawns has a unit direction
  const Geometry& g = *hit->geometry;
  if (g.emitter >= 0) {
    if (vertex == 0 && scene.hide_emitters()) {
      // Mitsuba's hide_emitters: the camera ray goes on through the emitter, as if unseen
      // (the same vertex again).
      pass_through(path.ray, *hit);
      return true;
    }
    add_emission(scene, path, *hit, wo);
  }
  // Vertex `vertex` closes segment vertex + 1; scattering here would add one more.
  if (max_depth >= 0 && vertex + 2 > max_depth) return false;

  // Each pair is drawn only where it is used (a pure function of its pair index, so the
  // numbers are the same as drawing all of them).
  const VertexContext c{.scene = scene,
                        .sampler = sampler,
                        .path = path,
                        .shadow = shadow,
                        .has_shadow = has_shadow,
                        .predrawn = predrawn,
                        .init_mixture = init_mixture,
                        .light_importance = light_importance,
                        .pair = kCameraPairs + kPairsPerVertex * uint32_t(vertex),
                        .roulette = vertex + 1 >= scene.rr_depth(),
                        .have_lights = !scene.lights().empty()};
  const RenderMaterial* m = &scene.material(g.material);

  // Mitsuba's mask: with probability 1 - opacity the hit is a null interaction, the path goes
  // straight on (null_scatter); shadow rays see the surface as opaque, and light through it
  // arrives by this null scattering with full weight. Past this point the vertex was chosen
  // with probability opacity, so its light sample and bounce are the nested material's,
  // weighed by f alone (not opacity f: that would count opacity twice, an image darker by the
  // factor opacity wherever it is fractional); the densities given to MIS (light sample here,
  // BSDF hit at the next vertex) are both opacity times the nested material's, as Mitsuba's
  // mask reports them, so the two weights still add to one.
  float opacity = 1;
  if (m->masked()) {
    opacity = opacity_at(*m, scene.textures(), *hit);
    sampler.set_pair(c.pair + 3);
    const glm::vec2 u_mask = sampler.get2d();
    if (u_mask.y >= opacity) return null_scatter(c, *hit);
  }

  SurfacePoint sp = hit->sp;
  m = facing_material(scene, m, wo, sp, *hit);
  if (!m) return false;  // one-sided surfaces are black from behind
  Scatter s;
  const bool scattered = m->type == MaterialType::diffuse && !m->textured
                             ? diffuse_vertex(c, *m, *hit, sp, opacity, &s)
                             : bsdf_vertex(c, *m, *hit, sp, wo, opacity, &s);
  return scattered && next_ray(path, s, sp, c.roulette);
}

}  // namespace tessera
