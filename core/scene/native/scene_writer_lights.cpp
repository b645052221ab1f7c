#include "scene/native/scene_writer_lights.h"

#include "scene/native/json_value.h"
#include "scene/scene_error.h"

namespace tessera::scene_writer {

std::string light_json(const Light& l, size_t index, const Names& names) {
  std::string what = "lights[" + std::to_string(index) + "] (" + printable(l.origin) + ")";
  static const char* kTypes[] = {"point", "spot", "directional", "constant", "envmap",
                                 "projector"};
  std::string out = std::string("    {\"type\": \"") + kTypes[int(l.kind)] + "\"";
  switch (l.kind) {
    case LightKind::point:
      out += ", \"intensity\": " + vec3(l.value, what);
      break;
    case LightKind::spot:
      out += ", \"intensity\": " + vec3(l.value, what) +
             ", \"cutoff_angle\": " + number(l.cutoff_angle_deg, what) +
             ", \"beam_width\": " + number(l.beam_width_deg, what);
      if (l.texture >= 0) out += ", \"texture\": " + texture_name(l.texture, names, what);
      break;
    case LightKind::directional:
      out += ", \"irradiance\": " + vec3(l.value, what);
      break;
    case LightKind::constant:
      out += ", \"radiance\": " + vec3(l.value, what);
      break;
    case LightKind::envmap:
      if (l.value.x != l.value.y || l.value.x != l.value.z) {
        throw SceneError(what + ": an envmap's scale is one number");
      }
      out += ", \"file\": " + json_string(valid_utf8(l.file)) +
             ", \"scale\": " + number(l.value.x, what);
      break;
    case LightKind::projector:
      out += ", \"irradiance\": " + vec3(l.value, what) +
             ", \"fov\": " + number(l.fov_x_deg, what) + ", \"aspect\": " + number(l.aspect, what);
      if (l.texture >= 0) out += ", \"texture\": " + texture_name(l.texture, names, what);
      break;
  }
  if (l.kind != LightKind::constant && l.to_world != glm::dmat4(1.0)) {
    out += ",\n      \"transform\": " + matrix_json(l.to_world, what);
  }
  return out + "}";
}

}  // namespace tessera::scene_writer
