#include "render/light/spot_light.h"

#include <cmath>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "accum/accumulation.h"
#include "render/warp.h"
#include "scene/scene_error.h"

namespace tessera {

SpotLight::SpotLight(const Light& light)
    : position_(glm::vec3(light.to_world[3])),
      world_to_local_(glm::inverse(glm::mat3(light.to_world))),
      intensity_(glm::vec3(light.value)) {
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
  const float f = falloff(glm::normalize(world_to_local_ * -wi).z);
  if (!(f > 0)) return s;
  s.distance = distance;
  s.wi = wi;
  s.radiance = intensity_ * (f / dist2);
  s.pdf = 1;
  s.delta = true;
  s.point = {position_, glm::vec3(0.0f), -wi};
  return s;
}

double SpotLight::power() const {
  const double cos_beam = double(cos_beam_), cos_cutoff = double(cos_cutoff_);
  return luminance(intensity_.x, intensity_.y, intensity_.z) * 2.0 * double(kPi) *
         ((1.0 - cos_beam) + (cos_beam - cos_cutoff) / 2.0);
}

}  // namespace tessera
