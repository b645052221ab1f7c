#include "render/light/directional_light.h"

#include <glm/geometric.hpp>
#include <limits>

#include "accum/accumulation.h"
#include "render/sampling/warp.h"

namespace tessera {

DirectionalLight::DirectionalLight(const Light& light)
    : wi_(-glm::normalize(glm::vec3(glm::dvec3(light.to_world[2])))),
      irradiance_(glm::vec3(light.value)) {}

LightSample DirectionalLight::sample() const {
  LightSample s;
  s.wi = wi_;
  s.distance = std::numeric_limits<float>::infinity();
  s.radiance = irradiance_;
  s.pdf = 1;
  s.delta = true;
  return s;
}

double DirectionalLight::power(double scene_radius) const {
  return double(kPi) * scene_radius * scene_radius *
         luminance(irradiance_.x, irradiance_.y, irradiance_.z);
}

}  // namespace tessera
