// The light of a shape: "emission" (radiance) or "power" (watts) (docs/scenes.md, "Lights").
#pragma once

#include <glm/vec3.hpp>
#include <optional>

#include "scene/native/json_value.h"
#include "scene/native/texture_parser.h"

namespace tessera {

/// What a shape object says about its light.
struct LightSpec {
  bool given = false;                 ///< "emission" or "power" is present
  glm::dvec3 emission{0};             ///< "emission": radiance (or a texture's scale), >= 0
  int32_t emission_texture = -1;      ///< "emission": {"texture": ...}: Shape::emission_texture
  std::optional<glm::dvec3> power_w;  ///< "power": flux in watts, each channel >= 0
};

/// Reads "emission" ([r,g,b] >= 0, or {"texture": name, "scale": s} naming one of `textures`)
/// and "power" (a number >= 0 for grey, or [r,g,b] >= 0) of the shape object `shape`; both at
/// once is an error.
LightSpec parse_light(const JsonValue& shape, const TextureNames& textures);

/// The radiance of a light given by `spec` on a shape of world-space `area`: the emission as
/// given, or power / (pi * area), halved again when the shape emits from both sides (the power
/// spreads over both). Throws SceneError when the area is not positive, or when the radiance
/// overflows.
glm::dvec3 light_radiance(const LightSpec& spec, double area, bool two_sided,
                          const JsonValue& shape);

}  // namespace tessera
