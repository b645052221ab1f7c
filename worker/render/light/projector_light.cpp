#include "render/light/projector_light.h"

#include <cmath>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "accum/accumulation.h"
#include "render/sampling/warp.h"
#include "scene/scene_error.h"

namespace tessera {

ProjectorLight::ProjectorLight(const Light& light, TextureLookup textures)
    : position_(glm::vec3(light.to_world[3])),
      world_to_local_(glm::inverse(glm::mat3(light.to_world))),
      irradiance_(glm::vec3(light.value)),
      texture_(light.texture),
      textures_(std::move(textures)),
      aspect_(float(light.aspect)) {
  if (!(light.fov_x_deg > 0 && light.fov_x_deg < 180) || !(light.aspect > 0) ||
      !std::isfinite(light.aspect)) {
    throw SceneError(light.origin + ": a projector needs 0 < fov (" +
                     std::to_string(light.fov_x_deg) + ") < 180 degrees and aspect (" +
                     std::to_string(light.aspect) + ") > 0");
  }
  tan_half_x_ = float(std::tan(light.fov_x_deg * (3.14159265358979323846 / 360.0)));
  if (texture_ >= 0) {
    if (!textures_) throw SceneError(light.origin + ": projector texture without a texture set");
    constexpr int kGrid = 64;
    double sum = 0;
    for (int j = 0; j < kGrid; ++j) {
      for (int i = 0; i < kGrid; ++i) {
        const glm::vec3 c = textures_(texture_, glm::vec2((i + 0.5f) / kGrid, (j + 0.5f) / kGrid));
        sum += luminance(c.x, c.y, c.z);
      }
    }
    texture_mean_ = sum / (kGrid * kGrid);
  }
}

glm::vec2 ProjectorLight::uv_of(glm::vec3 local) const {
  const float s = 0.5f / (local.z * tan_half_x_);
  return glm::vec2(0.5f - local.x * s, 0.5f - aspect_ * local.y * s);
}

LightSample ProjectorLight::sample(glm::vec3 ref) const {
  LightSample s;
  const glm::vec3 to_light = position_ - ref;
  const float dist2 = glm::dot(to_light, to_light);
  if (!(dist2 > 0) || !std::isfinite(dist2)) return s;
  const glm::vec3 local = world_to_local_ * -to_light;
  if (!(local.z > 0)) return s;  // behind the projector, or in its plane
  const glm::vec2 uv = uv_of(local);
  if (!(uv.x >= 0 && uv.x <= 1 && uv.y >= 0 && uv.y <= 1)) return s;
  glm::vec3 irradiance = irradiance_;
  if (texture_ >= 0) irradiance *= textures_(texture_, uv);
  const float distance = std::sqrt(dist2);
  const float cos_theta = local.z / distance;
  s.distance = distance;
  s.wi = to_light / distance;
  s.radiance = irradiance * (kPi / (local.z * local.z * cos_theta));
  s.pdf = 1;
  s.delta = true;
  s.point = {position_, glm::vec3(0.0f), -s.wi};
  return s;
}

double ProjectorLight::power() const {
  const double width = 2.0 * double(tan_half_x_);
  const double area = width * (width / double(aspect_));
  return double(kPi) * luminance(irradiance_.x, irradiance_.y, irradiance_.z) * texture_mean_ *
         area;
}

LightBounds ProjectorLight::bounds() const {
  LightBounds b;
  b.center = position_;
  b.phi = 4.0 * double(kPi) * double(kPi) * luminance(irradiance_.x, irradiance_.y, irradiance_.z) *
          texture_mean_;
  b.w = glm::normalize(glm::inverse(world_to_local_) * glm::vec3(0.0f, 0.0f, 1.0f));
  // The image's corner at z = 1: (tan(fov_x / 2), tan(fov_x / 2) / aspect, 1).
  const double tx = double(tan_half_x_), ty = tx / double(aspect_);
  b.cos_theta_o = float(1.0 / std::sqrt(1.0 + tx * tx + ty * ty));
  b.cos_theta_e = 1;  // along its normals only (LightImportance allows kReachSlack)
  return b;
}

}  // namespace tessera
