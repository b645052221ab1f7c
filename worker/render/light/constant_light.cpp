#include "render/light/constant_light.h"

#include "accum/accumulation.h"
#include "render/sampling/warp.h"

namespace tessera {

ConstantLight::ConstantLight(const Light& light) : radiance_(glm::vec3(light.value)) {}

glm::vec3 ConstantLight::sample(glm::vec2 u, float* pdf) const {
  *pdf = this->pdf();
  return square_to_uniform_sphere(u);
}

float ConstantLight::pdf() const { return 1.0f / (4.0f * kPi); }

double ConstantLight::power(double scene_radius) const {
  const double pi = double(kPi);
  return pi * scene_radius * scene_radius * 4.0 * pi *
         luminance(radiance_.x, radiance_.y, radiance_.z);
}

}  // namespace tessera
