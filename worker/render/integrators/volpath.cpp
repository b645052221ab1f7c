#include "render/integrators/volpath.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "render/bsdf/thin_dielectric.h"
#include "render/integrators/path_vertex.h"
#include "render/media/medium.h"

namespace tessera {
namespace {

constexpr double kVolumeMaxSurvival = 0.95;

double max_channel(const glm::dvec3& v) { return std::max(v.x, std::max(v.y, v.z)); }

/// The key of the tracking streams of event pair `pair`: its independent pair's 48 bits, with
/// `salt` to tell the free flight's stream from the shadow rays'.
uint64_t stream_key(PixelSampler& sampler, uint32_t pair, uint64_t salt) {
  sampler.set_pair(pair);
  const glm::vec2 u = sampler.get2d_independent();
  const uint64_t bits = uint64_t(u.x * 0x1p24f) << 24 | uint64_t(u.y * 0x1p24f);
  return mix64(bits ^ (salt * 0x9e3779b97f4a7c15ull));
}

/// The medium a ray along d enters at hit `h` (`ng_front` the shape's front normal there):
/// the shape's exterior when d leaves by its front, its interior otherwise; `current` when the
/// shape bounds no medium (Mitsuba's is_medium_transition / target_medium).
int32_t medium_after(const TraceableScene& scene, const Hit& h, glm::vec3 ng_front, glm::vec3 d,
                     int32_t current) {
  const glm::ivec2 sides = scene.medium_sides(h.geometry_id);
  if (sides.x < 0 && sides.y < 0) return current;
  return glm::dot(d, ng_front) > 0 ? sides.y : sides.x;
}

/// What passes straight through the surface at `h` along d (Mitsuba's eval_null_transmission):
/// 1 - opacity of a mask (a null BSDF: all), plus opacity times a thindielectric's (1 - R')
/// specular_transmittance; 0 for every other surface.
glm::vec3 null_transmission(const TraceableScene& scene, const Hit& h, glm::vec3 d) {
  const RenderMaterial& m = scene.material(h.geometry->material);
  glm::vec3 thin(0.0f);
  if (m.type == MaterialType::thin_glass) {
    const BsdfParams p = bsdf_params(m, scene.textures(), path_vertex_detail::texture_point(h));
    thin = (1.0f - thin_sheet_reflectance(std::abs(glm::dot(d, h.sp.ng)), p.eta)) * p.specular_transmittance;
  }
  if (!m.masked()) return thin;
  const float opacity = path_vertex_detail::opacity_at(m, scene.textures(), h);
  return (1.0f - opacity) + opacity * thin;
}

/// The fraction of light sample `ls` that reaches `origin` (already off its surface) through
/// the media and null surfaces between, starting in `medium`.
glm::dvec3 shadow_transmittance(const TraceableScene& scene, glm::vec3 origin, const LightSample& ls,
                                int32_t medium, TrackingStream& stream, PathCounters& counters) {
  glm::dvec3 tr(1.0);
  glm::vec3 o = origin;
  const bool at_infinity = std::isinf(ls.distance);
  const glm::vec3 target = at_infinity ? glm::vec3(0.0f) : offset_ray_origin(ls.point, -ls.wi);
  // As set_shadow_ray (vertex_shading.h): a delta light's ray ends short of it.
  const float end = ls.delta ? path_vertex_detail::kDeltaShadowEnd : 1.0f;
  for (int crossing = 0; crossing < kMaxShadowCrossings; ++crossing) {
    Ray r{o, ls.wi, std::numeric_limits<float>::infinity()};
    if (!at_infinity) {
      const glm::vec3 v = target - o;
      const float length = glm::length(v);
      if (!(length > 0)) return tr;
      r.d = v / length;
      r.t_max = length * end;
    }
    Hit h;
    ++counters.shadow_rays;
    const bool found = scene.intersect(r, &h);
    const float segment = found ? glm::length(h.sp.p - o) : r.t_max;
    if (medium >= 0) {
      tr *= scene.medium(medium).transmittance(o, r.d, segment, stream, scene.textures());
    }
    if (!found || !(max_channel(tr) > 0)) return found ? glm::dvec3(0.0) : tr;
    const glm::vec3 pass = null_transmission(scene, h, r.d);
    if (!(std::max({pass.x, pass.y, pass.z}) > 0)) return glm::dvec3(0.0);
    tr *= glm::dvec3(pass);
    medium = medium_after(scene, h, h.sp.ng, r.d, medium);
    o = offset_ray_origin(h.sp, r.d);
  }
  return glm::dvec3(0.0);
}

/// One volumetric path between its events: what it has gathered, its throughput, the medium it
/// is in, and the state the next emitter hit's MIS weight reads. trace_volume_path() runs its
/// events in order; each step says whether the path goes on.
class VolumePath {
 public:
  enum class Step { surface, next, end };

  VolumePath(const TraceableScene& scene, int max_depth, PixelSampler& sampler, PathCounters& counters)
      : scene_(scene), lights_(scene.lights()), textures_(scene.textures()), sampler_(sampler), counters_(counters),
        max_depth_(max_depth), have_lights_(!lights_.empty()), hide_(scene.hide_emitters()),
        medium_(scene.camera_medium()), rr_depth_(scene.rr_depth()) {}

  bool depth_left() const { return !(max_depth_ >= 0 && depth_ >= max_depth_); }
  bool in_medium() const { return medium_ >= 0; }
  const glm::dvec3& radiance() const { return radiance_; }

  /// The medium before the hit at t_hit (infinity: none): its transmittance, or a scattering
  /// event there (Step::next) with its light sample and phase-function bounce.
  Step through_medium(Ray& ray, uint32_t pair, float t_hit);
  /// The ray escaped: the environment's light.
  void escape(const Ray& ray);
  /// The surface at `hit`: its emission, a mask's null part (Step::next without an event), its
  /// light sample and BSDF bounce.
  Step at_surface(Ray& ray, uint32_t pair, Hit& hit);

 private:
  /// Russian roulette from the rr_depth-th scattering event on (counted from 1), as trace_path
  /// starts it at its rr_depth-th vertex.
  bool roulette(float u) {
    if (depth_ < rr_depth_) return true;
    const double survival = std::min(max_channel(beta_) * eta_scale_, kVolumeMaxSurvival);
    if (!(double(u) < survival)) return false;
    beta_ /= survival;
    return true;
  }

  const TraceableScene& scene_;
  const LightSet& lights_;
  const TextureSet& textures_;
  PixelSampler& sampler_;
  PathCounters& counters_;
  const int max_depth_;
  const bool have_lights_;
  const bool hide_;
  glm::dvec3 radiance_{0.0}, beta_{1.0};
  int32_t medium_;
  int depth_ = 0;             ///< scattering events so far (null interactions do not count)
  bool count_direct_ = true;  ///< an emitter hit counts fully: camera ray, delta chain, no NEE
  float prev_pdf_ = 0;        ///< direction density of the last scattering event
  SurfacePoint prev_sp_{};    ///< where it was (ng 0 for a medium point)
  double eta_scale_ = 1;
  const int rr_depth_;
};

VolumePath::Step VolumePath::through_medium(Ray& ray, uint32_t pair, float t_hit) {
  const RenderMedium& m = scene_.medium(medium_);
  sampler_.set_pair(pair);
  const glm::vec2 u_flight = sampler_.get2d();
  TrackingStream stream(stream_key(sampler_, pair + 5, 0));
  const FreeFlight flight = m.sample_flight(ray.o, ray.d, t_hit, u_flight.x, u_flight.y, stream, textures_);
  beta_ *= flight.weight;
  if (!(max_channel(beta_) > 0)) return Step::end;
  if (!flight.scattered) return Step::surface;
  const glm::vec3 p = ray.o + flight.t * ray.d;
  ++depth_;
  if (!depth_left()) return Step::end;
  const SurfacePoint sp{p, glm::vec3(0.0f), glm::vec3(0.0f)};
  sampler_.set_pair(pair + 1);
  const glm::vec2 u_choice = sampler_.get2d_independent();
  if (m.sample_emitters && have_lights_) {
    sampler_.set_pair(pair + 2);
    const LightSample ls = lights_.sample(sp, u_choice.x, sampler_.get2d());
    if (ls.pdf > 0 && ls.radiance != glm::vec3(0.0f)) {
      const float phase = m.phase.eval(ray.d, ls.wi);
      TrackingStream shadow_stream(stream_key(sampler_, pair + 5, 1));
      const glm::dvec3 tr = shadow_transmittance(scene_, p, ls, medium_, shadow_stream, counters_);
      const float w = ls.delta ? 1.0f : path_vertex_detail::mis_weight(ls.pdf, phase);
      radiance_ += beta_ * glm::dvec3(ls.radiance) * tr * (double(phase) * double(w) / double(ls.pdf));
    }
  }
  sampler_.set_pair(pair + 3);
  const PhaseSample ps = m.phase.sample(ray.d, sampler_.get2d());
  beta_ *= double(ps.weight);
  prev_pdf_ = ps.pdf;
  prev_sp_ = sp;
  count_direct_ = !m.sample_emitters;
  ray = Ray{p, ps.wi, std::numeric_limits<float>::infinity()};
  return roulette(u_choice.y) ? Step::next : Step::end;
}

void VolumePath::escape(const Ray& ray) {
  if (lights_.has_environment() && !(depth_ == 0 && hide_)) {
    const glm::vec3 le = lights_.environment(ray.d);
    const float w = path_vertex_detail::environment_weight(lights_, count_direct_, prev_pdf_, prev_sp_, ray.d);
    radiance_ += beta_ * glm::dvec3(le) * double(w);
  }
}

VolumePath::Step VolumePath::at_surface(Ray& ray, uint32_t pair, Hit& hit) {
  using namespace path_vertex_detail;
  const Geometry& g = *hit.geometry;
  const glm::vec3 wo = -ray.d;
  const glm::vec3 ng_front = hit.sp.ng;
  // Mitsuba's volpath hides an emitter the camera sees by leaving its emission out; the
  // surface is shaded all the same (its path integrator and trace_path let the ray pass).
  if (g.emitter >= 0 && !(depth_ == 0 && hide_)) {
    const glm::vec3 le = lights_.emitted(g, hit.primitive, hit.uv, hit.sp.ng, wo);
    if (le != glm::vec3(0.0f)) {
      const float w = emitter_hit_weight(lights_, count_direct_, prev_pdf_, prev_sp_, hit);
      radiance_ += beta_ * glm::dvec3(le) * double(w);
    }
  }
  const RenderMaterial* m = &scene_.material(g.material);
  float opacity = 1;
  if (m->masked()) {
    opacity = opacity_at(*m, textures_, hit);
    sampler_.set_pair(pair + 4);
    if (sampler_.get2d().y >= opacity) {
      // Passes straight on: a mask's null part. No scattering event: depth and the MIS state stay.
      medium_ = medium_after(scene_, hit, ng_front, ray.d, medium_);
      ray.o = offset_ray_origin(hit.sp, ray.d);
      ray.t_max = std::numeric_limits<float>::infinity();
      return Step::next;
    }
  }
  SurfacePoint sp = hit.sp;
  m = facing_material(scene_, m, wo, sp, hit);
  if (!m) return Step::end;  // one-sided surfaces are black from behind
  const ShadingFrame shading = shading_frame(hit, *m, textures_, scene_.has_uv(), wo);
  const Bsdf bsdf(bsdf_params(*m, textures_, texture_point(hit)));
  const glm::vec3 wo_local = shading.frame.to_local(wo);
  sampler_.set_pair(pair + 1);
  const glm::vec2 u_choice = sampler_.get2d_independent();
  // Mitsuba's volpath samples a light only where the next segment may still count.
  if (have_lights_ && bsdf.has_smooth_lobe() && (max_depth_ < 0 || depth_ + 1 < max_depth_)) {
    sampler_.set_pair(pair + 2);
    const LightSample ls = lights_.sample(sp, u_choice.x, sampler_.get2d());
    if (const std::optional<LightTerm> lt = light_term(bsdf, shading, wo_local, ls, *m, sp, opacity)) {
      const glm::vec3 origin = offset_ray_origin(sp, ls.wi);
      const int32_t shadow_medium = medium_after(scene_, hit, ng_front, ls.wi, medium_);
      TrackingStream shadow_stream(stream_key(sampler_, pair + 5, 1));
      const glm::dvec3 tr = shadow_transmittance(scene_, origin, ls, shadow_medium, shadow_stream, counters_);
      radiance_ += beta_ * glm::dvec3(lt->f) * glm::dvec3(ls.radiance) * tr * (double(lt->w) / double(ls.pdf));
    }
  }
  sampler_.set_pair(pair + 4);
  const float u_lobe = sampler_.get2d().x;
  sampler_.set_pair(pair + 3);
  const glm::vec2 u_bsdf = sampler_.get2d();
  const std::optional<BsdfSample> bs = bsdf.sample(wo_local, u_lobe, u_bsdf);
  if (!bs) return Step::end;
  const std::optional<ScatteredDirection> out = scattered_direction(shading, *bs, *m, sp);
  if (!out) return Step::end;
  const glm::vec3 wi = out->wi;
  beta_ *= glm::dvec3(bs->weight * out->perturbation);
  if (!(max_channel(beta_) > 0)) return Step::end;
  // A thindielectric's straight transmission is a null interaction in Mitsuba (its BSDF
  // samples it as BSDFFlags::Null): no depth, no new MIS state.
  const bool null_event = m->type == MaterialType::thin_glass && glm::dot(wi, ng_front) * glm::dot(wo, ng_front) < 0;
  medium_ = medium_after(scene_, hit, ng_front, wi, medium_);
  ray = Ray{offset_ray_origin(sp, wi), wi, std::numeric_limits<float>::infinity()};
  if (null_event) return Step::next;
  ++depth_;
  eta_scale_ *= double(bs->eta) * double(bs->eta);
  prev_pdf_ = bs->pdf * opacity;
  prev_sp_ = sp;
  count_direct_ = bs->delta;
  return roulette(u_choice.y) ? Step::next : Step::end;
}

}  // namespace

glm::dvec3 trace_volume_path(const TraceableScene& scene, Ray ray, int max_depth, PixelSampler& sampler,
                             PathCounters& counters) {
  VolumePath path(scene, max_depth, sampler, counters);
  for (uint32_t event = 0; event < kMaxVolumeEvents && path.depth_left(); ++event) {
    const uint32_t pair = kCameraPairs + kVolumePairsPerEvent * event;
    Hit hit;
    ++counters.rays;
    const bool found = scene.intersect(ray, &hit);
    const float t_hit = found ? glm::length(hit.sp.p - ray.o) : std::numeric_limits<float>::infinity();
    if (path.in_medium()) {
      const VolumePath::Step step = path.through_medium(ray, pair, t_hit);
      if (step == VolumePath::Step::end) break;
      if (step == VolumePath::Step::next) continue;
    }
    if (!found) {
      path.escape(ray);
      break;
    }
    if (path.at_surface(ray, pair, hit) == VolumePath::Step::end) break;
  }
  return path.radiance();
}

}  // namespace tessera
