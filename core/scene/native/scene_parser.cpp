#include "scene/native/scene_parser.h"

#include <map>

#include "scene/mesh/mesh_attribute_use.h"
#include "scene/native/json_document.h"
#include "scene/native/light_parser.h"
#include "scene/native/material_parser.h"
#include "scene/native/medium_parser.h"
#include "scene/native/settings_parser.h"
#include "scene/native/shape_parser.h"
#include "scene/native/texture_parser.h"
#include "scene/scene_error.h"
#include "scene/volume_texture_check.h"

namespace tessera {
namespace {

constexpr int kFormatVersion = 1;

void check_version(const JsonValue& root) {
  JsonValue version = root.at("tessera");
  if (!version.json().is_number()) version.fail("must be the format version, 1");
  int64_t v = version.integer(INT64_MIN, INT64_MAX);
  if (v != kFormatVersion) {
    version.fail("unsupported format version " + std::to_string(v) + " (this build reads 1)");
  }
}

/// "groups": name -> {"shapes": [...]}; group shapes are triangles or spheres, not lights.
std::map<std::string, uint32_t> parse_groups(const JsonValue& value, ShapeContext& context,
                                             Scene& scene) {
  std::map<std::string, uint32_t> names;
  for (const auto& [name, group_value] : value.members()) {
    if (name.empty()) group_value.fail("a group name must not be empty");
    group_value.expect_object({"shapes"}, "a group");
    ShapeGroup group;
    group.name = name;
    group.origin = group_value.path();
    for (const JsonValue& shape : group_value.at("shapes").elements()) {
      size_t first = group.shapes.size();
      parse_shape(shape, context, group.shapes);
      for (size_t i = first; i < group.shapes.size(); ++i) {
        if (group.shapes[i].is_emitter()) shape.fail("shapes in a group cannot emit light");
      }
    }
    if (group.shapes.empty()) group_value.at("shapes").fail("a group needs at least one shape");
    names[name] = uint32_t(scene.groups.size());
    scene.groups.push_back(std::move(group));
  }
  return names;
}

}  // namespace

Scene parse_native_scene(const JsonValue& root, const FileReader& reader) {
  root.expect_object({"tessera", "camera", "film", "render", "textures", "materials", "groups",
                      "shapes", "lights", "media"},
                     "a scene");
  check_version(root);
  Scene scene;
  if (std::optional<JsonValue> camera = root.find("camera")) scene.camera = parse_camera(*camera);
  if (std::optional<JsonValue> film = root.find("film")) scene.film = parse_film(*film);
  if (std::optional<JsonValue> render = root.find("render")) scene.render = parse_render(*render);
  TextureNames textures;
  if (std::optional<JsonValue> t = root.find("textures")) {
    textures = parse_textures(*t, scene.textures, scene.referenced_files, reader);
  }
  MediumNames media;
  if (std::optional<JsonValue> m = root.find("media")) {
    media = parse_media(*m, scene.textures, textures, scene.media);
  }
  if (std::optional<JsonValue> camera = root.find("camera")) {
    if (std::optional<JsonValue> medium = camera->find("medium")) {
      scene.camera.medium = medium_index(*medium, media);
    }
  }
  MaterialTable materials;
  if (std::optional<JsonValue> m = root.find("materials")) parse_materials(*m, materials, textures);
  ShapeContext context{materials, reader, scene.referenced_files, textures, nullptr, nullptr};
  std::map<std::string, uint32_t> groups;
  if (std::optional<JsonValue> g = root.find("groups")) groups = parse_groups(*g, context, scene);
  context.groups = &groups;
  context.media = &media;
  if (std::optional<JsonValue> shapes = root.find("shapes")) {
    for (const JsonValue& shape : shapes->elements()) parse_shape(shape, context, scene.shapes);
  }
  if (std::optional<JsonValue> lights = root.find("lights")) {
    scene.lights = parse_lights(*lights, textures, scene.referenced_files);
  }
  scene.materials = materials.take();
  check_mesh_attribute_use(scene);
  check_volume_texture_use(scene);
  return scene;
}

Scene parse_scene_text(std::string_view json_text, const std::string& source_name,
                       const FileReader& reader) {
  Json document = parse_json_document(json_text, source_name);
  if (!document.is_object()) {
    throw SceneError(source_name + ": a scene must be a JSON object ({\"tessera\": 1, ...})");
  }
  JsonValue root(document, "");
  return parse_native_scene(root, reader);
}

Scene parse_scene(std::string_view json_text, const FileReader& reader) {
  Scene scene = parse_scene_text(json_text, "scene", reader);
  scene.files = reader;
  return scene;
}

}  // namespace tessera
