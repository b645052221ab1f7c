#include "render/media/medium.h"

#include <algorithm>

#include <glm/matrix.hpp>

#include "scene/volume_grid_file.h"

namespace tessera {
namespace {

float channel_mean(glm::vec3 v) { return (v.x + v.y + v.z) * (1.0f / 3.0f); }

/// The largest value of a volume texture's grid (or its constant), for the majorant.
float volume_maximum(const Texture& t) {
  if (!t.grid) return float(std::max({t.value.x, t.value.y, t.value.z}));
  float m = 0;
  for (float v : t.grid->values) m = std::max(m, v);
  return m;
}

}  // namespace

RenderMedium make_render_medium(const Medium& m, const std::vector<Texture>& textures) {
  RenderMedium r;
  r.kind = m.kind;
  r.sigma_t = glm::vec3(m.sigma_t.value * m.scale);
  r.albedo = glm::vec3(m.albedo.value);
  r.sigma_t_texture = m.sigma_t.texture;
  r.albedo_texture = m.albedo.texture;
  r.phase = PhaseFunction(m.phase == PhaseKind::hg ? float(m.g) : 0.0f);
  r.sample_emitters = m.sample_emitters;
  if (m.kind == MediumKind::heterogeneous) {
    float grid_max = 1;
    if (r.sigma_t_texture >= 0) {
      const Texture& t = textures[size_t(r.sigma_t_texture)];
      grid_max = volume_maximum(t);
      // Empty outside the volume's box (a constvolume's too: Mitsuba's Volume::bbox).
      r.bounded = true;
      r.world_to_grid = glm::mat4(glm::inverse(t.volume_to_world));
    }
    r.majorant = std::max({r.sigma_t.x, r.sigma_t.y, r.sigma_t.z}) * grid_max;
  }
  return r;
}

glm::vec3 RenderMedium::sigma_t_at(glm::vec3 p, const TextureSet& textures) const {
  if (sigma_t_texture < 0) return sigma_t;
  TexturePoint at;
  at.p = p;
  return sigma_t * glm::max(textures.lookup(sigma_t_texture, at), glm::vec3(0.0f));
}

glm::vec3 RenderMedium::albedo_at(glm::vec3 p, const TextureSet& textures) const {
  if (albedo_texture < 0) return albedo;
  TexturePoint at;
  at.p = p;
  return glm::clamp(albedo * textures.lookup(albedo_texture, at), glm::vec3(0.0f), glm::vec3(1.0f));
}

bool RenderMedium::clip(glm::vec3 o, glm::vec3 d, float t_max, float* t0, float* t1) const {
  *t0 = 0;
  *t1 = t_max;
  if (!bounded) return true;
  // The slabs of [0, 1]^3 in grid space, where the ray keeps its parameter t.
  const glm::vec3 og = glm::vec3(world_to_grid * glm::vec4(o, 1.0f));
  const glm::vec3 dg = glm::vec3(world_to_grid * glm::vec4(d, 0.0f));
  for (int a = 0; a < 3; ++a) {
    if (dg[a] == 0) {
      if (og[a] < 0 || og[a] > 1) return false;
      continue;
    }
    float ta = (0 - og[a]) / dg[a], tb = (1 - og[a]) / dg[a];
    if (ta > tb) std::swap(ta, tb);
    *t0 = std::max(*t0, ta);
    *t1 = std::min(*t1, tb);
  }
  return *t0 < *t1;
}

FreeFlight RenderMedium::sample_flight(glm::vec3 o, glm::vec3 d, float t_max, float u_channel,
                                       float u_distance, TrackingStream& stream,
                                       const TextureSet& textures) const {
  FreeFlight f;
  if (kind == MediumKind::homogeneous) {
    const int c = std::min(int(u_channel * 3.0f), 2);
    const float s = sigma_t[c];
    // -log(1 - u) / sigma: u < 1, so the distance is finite when sigma > 0.
    const double t = s > 0 ? -std::log1p(-double(u_distance)) / double(s) : std::numeric_limits<double>::infinity();
    if (t < double(t_max)) {
      const double pdf = homogeneous_flight_pdf(sigma_t, t);
      f.scattered = true;
      f.t = float(t);
      const glm::vec3 a = albedo_at(o + float(t) * d, textures);
      f.weight = pdf > 0 ? glm::dvec3(a) * glm::dvec3(sigma_t) * homogeneous_transmittance(sigma_t, t) / pdf
                         : glm::dvec3(0.0);
      return f;
    }
    // Reached the surface: the probability of that is the mean of the channels' transmittances.
    const glm::dvec3 tr = homogeneous_transmittance(sigma_t, double(t_max));
    const double p = (tr.x + tr.y + tr.z) / 3.0;
    f.weight = p > 0 ? tr / p : glm::dvec3(0.0);
    return f;
  }
  float t0, t1;
  if (!(majorant > 0) || !clip(o, d, t_max, &t0, &t1)) return f;
  double t = t0;
  for (;;) {
    t -= std::log1p(-double(stream.next())) / double(majorant);
    if (!(t < double(t1))) return f;  // reached the end of the medium's part of the ray
    const glm::vec3 p = o + float(t) * d;
    const glm::vec3 s = sigma_t_at(p, textures);
    const float mean = channel_mean(s);
    const float p_real = std::min(mean / majorant, 1.0f);
    if (stream.next() < p_real) {
      f.scattered = true;
      f.t = float(t);
      f.weight *= glm::dvec3(albedo_at(p, textures)) * glm::dvec3(s) / double(mean);
      return f;
    }
    // A null collision: each channel's weight (majorant - sigma_c) / (majorant (1 - p_real)).
    f.weight *= (double(majorant) - glm::dvec3(s)) / (double(majorant) - double(mean));
  }
}

glm::dvec3 RenderMedium::transmittance(glm::vec3 o, glm::vec3 d, float t_max, TrackingStream& stream,
                                       const TextureSet& textures) const {
  if (kind == MediumKind::homogeneous) return homogeneous_transmittance(sigma_t, double(t_max));
  float t0, t1;
  glm::dvec3 tr(1.0);
  if (!(majorant > 0) || !clip(o, d, t_max, &t0, &t1)) return tr;
  // Ratio tracking against the majorant; an infinite segment is cut where the transmittance
  // has become negligible (it only falls).
  double t = t0;
  for (;;) {
    t -= std::log1p(-double(stream.next())) / double(majorant);
    if (!(t < double(t1))) return tr;
    tr *= 1.0 - glm::dvec3(sigma_t_at(o + float(t) * d, textures)) / double(majorant);
    if (!(std::max({tr.x, tr.y, tr.z}) > 1e-12)) return glm::dvec3(0.0);
  }
}

}  // namespace tessera
