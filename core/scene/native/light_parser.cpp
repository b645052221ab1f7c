#include "scene/native/light_parser.h"

#include <algorithm>
#include <cmath>

#include "scene/native/transform_parser.h"
#include "scene/scene_error.h"
#include "scene/bundle_path.h"

namespace tessera {
namespace {

/// A number (grey) or [r, g, b], each >= 0.
glm::dvec3 non_negative_color(const JsonValue& value) {
  if (value.json().is_number()) {
    double grey = value.number();
    if (grey < 0) value.fail("must be >= 0 (got " + format_number(grey) + ")");
    return glm::dvec3(grey);
  }
  glm::dvec3 rgb = value.vec3();
  std::vector<JsonValue> channels = value.elements(3);
  for (int i = 0; i < 3; ++i) {
    if (rgb[i] < 0) channels[i].fail("must be >= 0 (got " + format_number(rgb[i]) + ")");
  }
  return rgb;
}

LightKind parse_kind(const JsonValue& value) {
  const std::string& type = value.string();
  if (type == "point") return LightKind::point;
  if (type == "spot") return LightKind::spot;
  if (type == "directional") return LightKind::directional;
  if (type == "constant") return LightKind::constant;
  if (type == "envmap") return LightKind::envmap;
  if (type == "projector") return LightKind::projector;
  value.fail("unknown light type \"" + printable(type) +
             "\" (expected point, spot, directional, constant, envmap or projector)");
}

std::vector<std::string_view> keys_of(LightKind kind) {
  switch (kind) {
    case LightKind::point:
      return {"type", "transform", "intensity"};
    case LightKind::spot:
      return {"type", "transform", "intensity", "cutoff_angle", "beam_width", "texture"};
    case LightKind::directional:
      return {"type", "transform", "irradiance"};
    case LightKind::constant:
      return {"type", "radiance"};
    case LightKind::envmap:
      return {"type", "transform", "file", "scale"};
    case LightKind::projector:
      return {"type", "transform", "irradiance", "texture", "fov", "aspect"};
  }
  return {};
}

glm::dmat4 rigid_transform(const JsonValue& value) {
  Transform transform = parse_transform(value);
  std::optional<double> scale = transform.similarity_scale();
  if (!scale || std::abs(*scale - 1) > 1e-6 || transform.flips_orientation()) {
    value.fail("a light's transform must be a rotation and a translation (no scale or mirror)");
  }
  return transform.matrix();
}

double angle(const JsonValue& light, const char* key, double fallback, double max) {
  std::optional<JsonValue> value = light.find(key);
  if (!value) return fallback;
  double degrees = value->number();
  if (!(degrees > 0 && degrees <= max)) {
    value->fail("must be in (0, " + format_number(max) + "] degrees (got " +
                format_number(degrees) + ")");
  }
  return degrees;
}

Light parse_light_object(const JsonValue& value, const TextureNames& textures,
                         std::vector<std::string>& referenced_files) {
  if (!value.json().is_object()) value.expect_object({}, "a light");
  Light light;
  light.origin = value.path();
  light.kind = parse_kind(value.at("type"));
  value.expect_object(keys_of(light.kind), "a \"" + value.at("type").string() + "\" light");
  if (auto t = value.find("transform")) light.to_world = rigid_transform(*t);
  const char* value_key = light.kind == LightKind::directional ||
                                  light.kind == LightKind::projector
                              ? "irradiance"
                          : light.kind == LightKind::constant  ? "radiance"
                          : light.kind == LightKind::envmap    ? "scale"
                                                               : "intensity";
  if (auto v = value.find(value_key)) {
    if (light.kind == LightKind::envmap && !v->json().is_number()) v->fail("must be a number");
    light.value = non_negative_color(*v);
  }
  if (light.kind == LightKind::spot) {
    light.cutoff_angle_deg = angle(value, "cutoff_angle", 20, 180);  // as Mitsuba
    light.beam_width_deg = angle(value, "beam_width", light.cutoff_angle_deg * 0.75,
                                 light.cutoff_angle_deg);
    if (auto t = value.find("texture")) light.texture = texture_index(*t, textures);
  }
  if (light.kind == LightKind::projector) {
    if (auto t = value.find("texture")) light.texture = texture_index(*t, textures);
    JsonValue fov = value.at("fov");
    light.fov_x_deg = fov.number();
    if (!(light.fov_x_deg > 0 && light.fov_x_deg < 180)) {
      fov.fail("must be in (0, 180) degrees (got " + format_number(light.fov_x_deg) + ")");
    }
    if (auto a = value.find("aspect")) {
      light.aspect = a->number();
      if (!(light.aspect > 0)) a->fail("must be > 0 (got " + format_number(light.aspect) + ")");
    }
  }
  if (light.kind == LightKind::envmap) {
    JsonValue file = value.at("file");
    light.file = check_bundle_path(file.string(), file.path());
    if (std::find(referenced_files.begin(), referenced_files.end(), light.file) ==
        referenced_files.end()) {
      referenced_files.push_back(light.file);
    }
  }
  return light;
}

}  // namespace

std::vector<Light> parse_lights(const JsonValue& value, const TextureNames& textures,
                               std::vector<std::string>& referenced_files) {
  std::vector<Light> lights;
  for (const JsonValue& light : value.elements()) {
    lights.push_back(parse_light_object(light, textures, referenced_files));
  }
  return lights;
}

}  // namespace tessera
