// Mitsuba's projector emitter (mitsuba3 src/emitters/projector.cpp): the reciprocal of a
// perspective camera. A point source at to_world's origin throws an image (the irradiance
// texture, or a constant) through the frustum of a pinhole camera looking along +z; the image
// plane at z = 1 receives pi * scale * irradiance(uv), a plane anywhere else the same image,
// scaled by the inverse square of its distance.
#pragma once

#include <cstdint>
#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "render/light/area_light.h"
#include "render/light/light_bounds.h"
#include "render/light/light_sample.h"
#include "scene/scene.h"

namespace tessera {

class ProjectorLight {
 public:
  /// light.kind == projector: to_world (rigid) places it, looking along +z; value = irradiance
  /// times Mitsuba's scale (with a texture: the scale alone); light.texture (when >= 0) looked
  /// up through `textures`, which must be safe to call from many threads; fov_x_deg (the
  /// horizontal field of view) and aspect (the image's width / height) shape the frustum.
  /// Throws SceneError naming light.origin unless 0 < fov_x_deg < 180 and aspect > 0, or when
  /// a texture has no lookup.
  ProjectorLight(const Light& light, TextureLookup textures = {});

  /// The light as seen from ref: pi * irradiance(uv) / (z^2 cos theta), with z the depth of
  /// ref in the light's frame and theta the angle between its axis and ref (Mitsuba's
  /// sample_direction), pdf 1 (delta); pdf 0 behind the projector or outside its image.
  LightSample sample(glm::vec3 ref) const;
  /// Where a point of the light's frame (z > 0) falls on the image, Mitsuba's
  /// perspective_projection: (0.5 - 0.5 x / (z t), 0.5 - 0.5 aspect y / (z t)), t =
  /// tan(fov_x / 2); inside the image when both are in [0, 1].
  glm::vec2 uv_of(glm::vec3 local) const;
  /// Emitted power, luminance-weighted: pi * irradiance * the image's area at z = 1, times
  /// the texture's mean luminance (a 64 x 64 grid of lookups). Only the light picker uses it.
  double power() const;
  /// What the light picker weighs it by (pbrt-v4's ProjectionLight::Bounds): a point light of
  /// its intensity on the axis (phi = 4 pi * pi irradiance, luminance, times the texture's
  /// mean) whose normals fill the cone through the image's corners, emitting along them only,
  /// so that its importance is 0 outside that cone.
  LightBounds bounds() const;

 private:
  glm::vec3 position_;
  glm::mat3 world_to_local_;
  glm::vec3 irradiance_;
  int32_t texture_ = -1;
  TextureLookup textures_;
  float tan_half_x_;  ///< tan(fov_x / 2)
  float aspect_;
  double texture_mean_ = 1;  ///< see power()
};

}  // namespace tessera
