#include "render/light/point_light.h"

#include <cmath>
#include <glm/geometric.hpp>

#include "accum/accumulation.h"
#include "render/sampling/warp.h"

namespace tessera {

PointLight::PointLight(const Light& light)
    : position_(glm::vec3(light.to_world[3])), intensity_(glm::vec3(light.value)) {}

LightSample PointLight::sample(glm::vec3 ref) const {
  LightSample s;
  const glm::vec3 to_light = position_ - ref;
  const float dist2 = glm::dot(to_light, to_light);
  if (!(dist2 > 0) || !std::isfinite(dist2)) return s;
  s.distance = std::sqrt(dist2);
  s.wi = to_light / s.distance;
  s.radiance = intensity_ / dist2;
  s.pdf = 1;
  s.delta = true;
  s.point = {position_, glm::vec3(0.0f), -s.wi};
  return s;
}

double PointLight::power() const {
  return 4.0 * double(kPi) * luminance(intensity_.x, intensity_.y, intensity_.z);
}

}  // namespace tessera
