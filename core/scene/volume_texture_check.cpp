#include "scene/volume_texture_check.h"

#include "scene/scene_error.h"

namespace tessera {
namespace {

bool is_volume(const Scene& scene, int32_t texture) {
  return texture >= 0 && size_t(texture) < scene.textures.size() &&
         scene.textures[size_t(texture)].kind == TextureKind::volume;
}

std::string texture_name(const Scene& scene, int32_t texture) {
  return "texture \"" + scene.textures[size_t(texture)].name + "\" (volume)";
}

void check_material(const Scene& scene, const Material& m) {
  if (is_volume(scene, m.bump_map)) {
    throw SceneError("material \"" + m.name + "\": " + texture_name(scene, m.bump_map) +
                     " cannot be a bump map (Mitsuba's volume texture has no gradient, "
                     "eval_1_grad)");
  }
  if (is_volume(scene, m.normal_map)) {
    throw SceneError("material \"" + m.name + "\": " + texture_name(scene, m.normal_map) +
                     " cannot be a normal map (Tessera looks normal maps up by (u, v) alone; "
                     "bake it into a bitmap)");
  }
  for (const Material& nested : m.blend) check_material(scene, nested);
}

void check_shape(const Scene& scene, const Shape& shape) {
  if (is_volume(scene, shape.emission_texture)) {
    throw SceneError(shape.origin + ": its emission is " +
                     texture_name(scene, shape.emission_texture) +
                     ", which Tessera does not read for emitters (it looks emitters' textures "
                     "up by (u, v) alone; bake it into a bitmap)");
  }
}

}  // namespace

std::shared_ptr<const VolumeGridFile> read_volume_texture_grid(std::string_view bytes,
                                                               const std::string& path) {
  auto grid = std::make_shared<VolumeGridFile>(parse_volume_grid_file(bytes, path));
  if (grid->channels != 1 && grid->channels != 3) {
    throw SceneError(path + ": has " + std::to_string(grid->channels) +
                     " channels; a volume texture reads 1 (grey) or 3 (RGB), as Mitsuba's "
                     "gridvolume does for colours");
  }
  return grid;
}

void check_volume_texture_use(const Scene& scene) {
  bool any = false;
  for (const Texture& t : scene.textures) any = any || t.kind == TextureKind::volume;
  if (!any) return;
  for (const Material& m : scene.materials) check_material(scene, m);
  for (const Light& light : scene.lights) {
    if (is_volume(scene, light.texture)) {
      throw SceneError(light.origin + ": its " + texture_name(scene, light.texture) +
                       " cannot be a light's texture (Tessera looks it up by direction or "
                       "(u, v), with no surface point)");
    }
  }
  for (const Shape& shape : scene.shapes) check_shape(scene, shape);
  for (const ShapeGroup& group : scene.groups) {
    for (const Shape& shape : group.shapes) check_shape(scene, shape);
  }
}

}  // namespace tessera
