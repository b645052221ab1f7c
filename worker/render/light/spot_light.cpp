#include "render/light/spot_light.h"

#include <cmath>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "accum/accumulation.h"
#include "render/sampling/warp.h"
#include "scene/scene_error.h"

namespace tessera {

SpotLight::SpotLight(const Light& light, TextureLookup textures)
    : position_(glm::vec3(light.to_world[3])),
      world_to_local_(glm::inverse(glm::mat3(light.to_world))),
      intensity_(glm::vec3(light.value)),
      texture_(light.texture),
      textures_(std::move(textures)) {
  if (!(light.beam_width_deg > 0) || !(light.beam_width_deg <= light.cutoff_angle_deg) ||
      !(light.cutoff_angle_deg <= 180)) {
    throw SceneError(light.origin + ": spot light needs 0 < beam_width (" +
                     std::to_string(light.beam_width_deg) + ") <= cutoff_angle (" +
                     std::to_string(light.cutoff_angle_deg) + ") <= 180 degrees");
  }
  cutoff_rad_ = float(light.cutoff_angle_deg * (3.14159265358979323846 / 180.0));
  beam_rad_ = float(light.beam_width_deg * (3.14159265358979323846 / 180.0));
  cos_cutoff_ = std::cos(cutoff_rad_);
  cos_beam_ = std::cos(beam_rad_);
  uv_factor_ = std::tan(cutoff_rad_);
  if (texture_ >= 0) {
    if (!textures_) throw SceneError(light.origin + ": spot light texture without a texture set");
    texture_mean_ = disc_mean_luminance();
  }
}

double SpotLight::disc_mean_luminance() const {
  constexpr int kGrid = 64;
  double sum = 0;
  int count = 0;
  for (int j = 0; j < kGrid; ++j) {
    for (int i = 0; i < kGrid; ++i) {
      const glm::vec2 uv((i + 0.5f) / kGrid, (j + 0.5f) / kGrid);
      const glm::vec2 offset = uv - glm::vec2(0.5f);
      if (glm::dot(offset, offset) > 0.25f) continue;
      const glm::vec3 c = textures_(texture_, uv);
      sum += luminance(c.x, c.y, c.z);
      ++count;
    }
  }
  return sum / count;
}

glm::vec2 SpotLight::uv_of(glm::vec3 d) const {
  return glm::vec2(0.5f + 0.5f * d.x / (d.z * uv_factor_), 0.5f + 0.5f * d.y / (d.z * uv_factor_));
}

float SpotLight::falloff(float cos_theta) const {
  if (!(cos_theta > cos_cutoff_)) return 0.0f;
  if (cos_theta >= cos_beam_) return 1.0f;
  // Here beam < theta < cutoff, so the transition width is > 0.
  return (cutoff_rad_ - std::acos(cos_theta)) / (cutoff_rad_ - beam_rad_);
}

LightSample SpotLight::sample(glm::vec3 ref) const {
  LightSample s;
  const glm::vec3 to_light = position_ - ref;
  const float dist2 = glm::dot(to_light, to_light);
  if (!(dist2 > 0) || !std::isfinite(dist2)) return s;
  const float distance = std::sqrt(dist2);
  const glm::vec3 wi = to_light / distance;
  const glm::vec3 local = glm::normalize(world_to_local_ * -wi);
  const float f = falloff(local.z);
  if (!(f > 0)) return s;
  glm::vec3 emitted = intensity_;
  if (texture_ >= 0) {
    const glm::vec2 uv = uv_of(local);
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) return s;  // d.z == 0: cutoff of 90 deg
    emitted *= textures_(texture_, uv);
  }
  s.distance = distance;
  s.wi = wi;
  s.radiance = emitted * (f / dist2);
  s.pdf = 1;
  s.delta = true;
  s.point = {position_, glm::vec3(0.0f), -wi};
  return s;
}

double SpotLight::power() const {
  const double cos_beam = double(cos_beam_), cos_cutoff = double(cos_cutoff_);
  return luminance(intensity_.x, intensity_.y, intensity_.z) * texture_mean_ * 2.0 *
         double(kPi) * ((1.0 - cos_beam) + (cos_beam - cos_cutoff) / 2.0);
}

LightBounds SpotLight::bounds() const {
  LightBounds b;
  b.center = position_;
  b.phi = 4.0 * double(kPi) * luminance(intensity_.x, intensity_.y, intensity_.z) * texture_mean_;
  b.w = glm::normalize(glm::inverse(world_to_local_) * glm::vec3(0.0f, 0.0f, 1.0f));
  b.cos_theta_o = cos_beam_;
  b.cos_theta_e = std::cos(cutoff_rad_ - beam_rad_);
  return b;
}

}  // namespace tessera
