#include "scene/mitsuba/mitsuba_emitter.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "scene/image_check.h"
#include "scene/mitsuba/mitsuba_plugin.h"
#include "scene/mitsuba/mitsuba_sensor.h"
#include "scene/mitsuba/mitsuba_transform.h"
#include "scene/message_text.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

constexpr MitsubaColorRole kEmission = MitsubaColorRole::emission;

glm::dvec3 non_negative(MitsubaPlugin& plugin, std::string_view name) {
  glm::dvec3 value = plugin.take_color(name, kEmission).value_or(glm::dvec3(1));
  for (int c = 0; c < 3; ++c) {
    if (!(value[c] >= 0)) {
      fail_at(*plugin.property(name),
              "each channel must be >= 0 (got " + format_number(value[c]) + ")");
    }
  }
  return value;
}

/// to_world, which must be a rotation and a translation (Mitsuba's tolerance, 1e-3).
glm::dmat4 rigid_to_world(MitsubaPlugin& plugin) {
  std::optional<Transform> to_world = plugin.take_transform("to_world");
  if (!to_world) return glm::dmat4(1.0);
  std::optional<double> scale = to_world->similarity_scale();
  if (!scale || std::abs(*scale - 1) > 1e-3 || to_world->flips_orientation()) {
    fail_at(*plugin.property("to_world"),
            "this emitter's to_world must be a rotation and a translation");
  }
  return to_world->matrix();
}

/// A frame whose +z is `direction` (a directional light is the same about its axis). The
/// direction is scaled by its largest component before it is normalised, so that neither a huge
/// one (1e308: its squared length overflows) nor a tiny one (1e-310: underflows) becomes NaN.
glm::dmat4 frame_along(const glm::dvec3& direction) {
  const double largest =
      std::max({std::abs(direction.x), std::abs(direction.y), std::abs(direction.z)});
  glm::dvec3 z = glm::normalize(direction / largest);
  glm::dvec3 helper = std::abs(z.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  glm::dvec3 x = glm::normalize(glm::cross(helper, z));
  glm::dvec3 y = glm::cross(z, x);
  glm::dmat4 m(1.0);
  m[0] = glm::dvec4(x, 0);
  m[1] = glm::dvec4(y, 0);
  m[2] = glm::dvec4(z, 0);
  return m;
}

void read_point(MitsubaPlugin& plugin, Light& light) {
  light.kind = LightKind::point;
  if (std::optional<glm::dvec3> position = plugin.take_point("position")) {
    if (plugin.property("to_world")) {
      fail_at(*plugin.property("to_world"), "give position or to_world, not both");
    }
    light.to_world[3] = glm::dvec4(*position, 1);
  } else {
    light.to_world = rigid_to_world(plugin);
  }
  light.value = non_negative(plugin, "intensity");
}

void read_spot(MitsubaPlugin& plugin, Light& light, MitsubaTextures& textures) {
  light.kind = LightKind::spot;
  light.to_world = rigid_to_world(plugin);
  light.value = non_negative(plugin, "intensity");
  if (std::optional<MitsubaObject> texture = plugin.take_named_object("texture")) {
    light.texture = textures.of(*texture->element);
    if (textures.at(light.texture).kind == TextureKind::rawconstant) {
      fail_at(*texture->written, "a spot's texture must vary over the cone, as Mitsuba demands "
                                 "(bitmap or checkerboard); give a constant as intensity");
    }
  } else if (const MitsubaElement* constant = plugin.property("texture")) {
    // Mitsuba refuses it too ("must be spatially varying"): a constant belongs in intensity.
    fail_at(*constant, "a spot's texture must be a <texture> (bitmap or checkerboard); give a "
                       "constant colour as intensity");
  }
  light.cutoff_angle_deg = plugin.take_float("cutoff_angle").value_or(20.0);
  light.beam_width_deg = plugin.take_float("beam_width").value_or(light.cutoff_angle_deg * 0.75);
  if (!(light.cutoff_angle_deg > 0 && light.cutoff_angle_deg <= 180)) {
    fail_at(*plugin.property("cutoff_angle"), "must be in (0, 180] degrees");
  }
  if (!(light.beam_width_deg > 0 && light.beam_width_deg <= light.cutoff_angle_deg)) {
    fail_at(plugin.property("beam_width") ? *plugin.property("beam_width") : plugin.element(),
            "beam_width must be in (0, cutoff_angle]");
  }
}

/// The width / height of what a projector shows, as Mitsuba's Texture::resolution gives it: a
/// bitmap's pixel size (its file decoded and checked here), 1 for anything else.
double projector_aspect(const MitsubaElement& where, const Texture& texture,
                        MitsubaFileResolver& files) {
  if (texture.kind != TextureKind::bitmap) return 1;
  try {
    const ImageCheck image = check_image_bytes(texture.file, files.read(texture.file));
    return double(image.width) / image.height;
  } catch (const SceneError& e) {
    fail_at(where, e.what());
  }
}

void read_projector(MitsubaPlugin& plugin, Light& light, MitsubaTextures& textures,
                    MitsubaFileResolver& files) {
  light.kind = LightKind::projector;
  light.to_world = rigid_to_world(plugin);
  const double scale = plugin.take_float("scale").value_or(1.0);
  if (!(scale >= 0)) {
    fail_at(*plugin.property("scale"), "must be >= 0 (got " + format_number(scale) + ")");
  }
  std::optional<MitsubaObject> texture = plugin.take_named_object("irradiance");
  if (texture) {
    light.texture = textures.of(*texture->element);
    light.value = glm::dvec3(scale);
    light.aspect = projector_aspect(*texture->element, textures.at(light.texture), files);
  } else {
    light.value = scale * non_negative(plugin, "irradiance");
    light.aspect = 1;
  }
  light.fov_x_deg = read_mitsuba_fov_x(plugin, light.aspect);
}

void read_directional(MitsubaPlugin& plugin, Light& light) {
  light.kind = LightKind::directional;
  if (std::optional<glm::dvec3> direction = plugin.take_point("direction")) {
    if (plugin.property("to_world")) {
      fail_at(*plugin.property("to_world"), "give direction or to_world, not both");
    }
    if (*direction == glm::dvec3(0)) fail_at(*plugin.property("direction"), "must not be 0");
    light.to_world = frame_along(*direction);
  } else {
    light.to_world = rigid_to_world(plugin);
  }
  light.value = non_negative(plugin, "irradiance");
}

void read_envmap(MitsubaPlugin& plugin, Light& light, MitsubaFileResolver& files,
                 std::vector<std::string>& referenced_files) {
  light.kind = LightKind::envmap;
  std::optional<std::string> filename = plugin.take_string("filename");
  if (!filename) fail_at(plugin.element(), "missing <string name=\"filename\">");
  light.file = files.resolve(*plugin.property("filename"), *filename);
  if (std::find(referenced_files.begin(), referenced_files.end(), light.file) ==
      referenced_files.end()) {
    referenced_files.push_back(light.file);
  }
  double scale = plugin.take_float("scale").value_or(1.0);
  if (!(scale >= 0)) {
    fail_at(*plugin.property("scale"), "must be >= 0 (got " + format_number(scale) + ")");
  }
  light.value = glm::dvec3(scale);
  light.to_world = rigid_to_world(plugin);
  plugin.ignore("mis_compensation");  // a sampling strategy: the same image, other noise
}

}  // namespace

MitsubaAreaEmission read_mitsuba_area_emitter(const MitsubaElement& element, const MitsubaIds& ids,
                                              MitsubaTextures& textures) {
  MitsubaPlugin emitter(element, ids);
  if (emitter.type() != "area") {
    fail_at(element,
            "a shape's emitter must be \"area\" (point, spot, directional, constant and envmap "
            "emitters stand at the top of the scene)");
  }
  TexturedColor radiance =
      read_textured_color(emitter, "radiance", glm::dvec3(1), kEmission, textures);
  emitter.ignore("sampling_weight");  // how often it is sampled: noise only
  emitter.finish();
  return MitsubaAreaEmission{radiance.value, radiance.texture};
}

Light read_mitsuba_light(const MitsubaElement& element, const MitsubaIds& ids,
                         MitsubaFileResolver& files, std::vector<std::string>& referenced_files,
                         MitsubaTextures& textures) {
  MitsubaPlugin plugin(element, ids);
  Light light;
  light.origin = element.where();
  const std::string& type = plugin.type();
  if (type == "point") {
    read_point(plugin, light);
  } else if (type == "spot") {
    read_spot(plugin, light, textures);
  } else if (type == "directional") {
    read_directional(plugin, light);
  } else if (type == "constant") {
    light.kind = LightKind::constant;
    light.value = non_negative(plugin, "radiance");
  } else if (type == "envmap") {
    read_envmap(plugin, light, files, referenced_files);
  } else if (type == "projector") {
    read_projector(plugin, light, textures, files);
  } else if (type == "area") {
    fail_at(element, "an area emitter belongs inside a <shape> (or is named by one with <ref>)");
  } else {
    fail_at(element,
            "unsupported emitter (Tessera has area, point, spot, directional, constant, envmap "
            "and projector)");
  }
  plugin.ignore("sampling_weight");  // how often it is sampled: noise only
  plugin.finish();
  return light;
}

}  // namespace tessera
