#include "scene/native/shape_light.h"

#include <cmath>
#include <numbers>

namespace tessera {
namespace {

glm::dvec3 non_negative_rgb(const JsonValue& value) {
  glm::dvec3 rgb = value.vec3();
  std::vector<JsonValue> channels = value.elements(3);
  for (int i = 0; i < 3; ++i) {
    if (rgb[i] < 0) channels[i].fail("must be >= 0 (got " + format_number(rgb[i]) + ")");
  }
  return rgb;
}

glm::dvec3 parse_power(const JsonValue& value) {
  if (!value.json().is_number()) return non_negative_rgb(value);
  double grey = value.number();
  if (grey < 0) value.fail("must be >= 0 (got " + format_number(grey) + ")");
  return glm::dvec3(grey);
}

}  // namespace

LightSpec parse_light(const JsonValue& shape, const TextureNames& textures) {
  LightSpec spec;
  std::optional<JsonValue> emission = shape.find("emission");
  std::optional<JsonValue> power = shape.find("power");
  if (emission && power) power->fail("give either emission or power, not both");
  if (emission && emission->json().is_object()) {
    TexturedColor color = parse_textured_color(*emission, textures, {0, 1e300});
    spec.emission = color.value;
    spec.emission_texture = color.texture;
  } else if (emission) {
    spec.emission = non_negative_rgb(*emission);
  }
  if (power) spec.power_w = parse_power(*power);
  spec.given = emission || power;
  return spec;
}

glm::dvec3 light_radiance(const LightSpec& spec, double area, bool two_sided,
                          const JsonValue& shape) {
  if (!(area > 0) || !std::isfinite(area)) {
    shape.fail("a light must have a positive, finite area (got " + format_number(area) + ")");
  }
  if (!spec.power_w) return spec.emission;
  glm::dvec3 radiance = *spec.power_w / (std::numbers::pi * area * (two_sided ? 2.0 : 1.0));
  if (!std::isfinite(radiance.x) || !std::isfinite(radiance.y) || !std::isfinite(radiance.z)) {
    shape.fail("the radiance of this power overflows (the shape's area is too small)");
  }
  return radiance;
}

}  // namespace tessera
