#include "scene/mesh/mesh_attribute_use.h"

#include <string>
#include <vector>

#include "scene/scene_error.h"

namespace tessera {
namespace {

bool is_attribute(const Scene& scene, int32_t texture) {
  return texture >= 0 && size_t(texture) < scene.textures.size() &&
         scene.textures[size_t(texture)].kind == TextureKind::mesh_attribute;
}

/// The textures that `m` (and the materials it nests) looks up at a shape's hit.
void material_textures(const Material& m, std::vector<int32_t>& out) {
  for (const TexturedColor* c : {&m.reflectance, &m.specular_reflectance,
                                 &m.specular_transmittance}) {
    out.push_back(c->texture);
  }
  const PrincipledParameters& p = m.principled;
  for (const TexturedFloat* f :
       {&m.alpha_u, &m.alpha_v, &m.opacity, &m.blend_weight, &p.roughness, &p.anisotropic,
        &p.metallic, &p.spec_trans, &p.spec_tint, &p.sheen, &p.sheen_tint, &p.flatness,
        &p.clearcoat, &p.clearcoat_gloss, &p.diff_trans}) {
    out.push_back(f->texture);
  }
  out.push_back(m.ior_texture);
  for (const Material& nested : m.blend) material_textures(nested, out);
}

std::string texture_name(const Scene& scene, int32_t texture) {
  return "texture \"" + scene.textures[size_t(texture)].name + "\"";
}

void check_no_gradient(const Scene& scene, const Material& m) {
  for (int32_t map : {m.normal_map, m.bump_map}) {
    if (is_attribute(scene, map)) {
      throw SceneError("material \"" + m.name + "\": " + texture_name(scene, map) +
                       " (mesh_attribute) cannot be a normal or bump map (Mitsuba's "
                       "mesh_attribute has no gradient)");
    }
  }
  for (const Material& nested : m.blend) check_no_gradient(scene, nested);
}

void check_shape(const Scene& scene, const Shape& shape) {
  if (shape.kind == Shape::Kind::instance) return;
  if (is_attribute(scene, shape.emission_texture)) {
    throw SceneError(shape.origin + ": its emission is " +
                     texture_name(scene, shape.emission_texture) +
                     " (mesh_attribute), which Tessera does not read for emitters");
  }
  std::vector<uint32_t> materials = {shape.material};
  if (shape.material < scene.materials.size() && scene.materials[shape.material].back >= 0) {
    materials.push_back(uint32_t(scene.materials[shape.material].back));
  }
  for (uint32_t index : materials) {
    if (index >= scene.materials.size()) continue;
    const Material& m = scene.materials[index];
    std::vector<int32_t> textures;
    material_textures(m, textures);
    for (int32_t t : textures) {
      if (!is_attribute(scene, t)) continue;
      const std::string& name = scene.textures[size_t(t)].attribute;
      if (find_mesh_attribute(shape.attributes, name)) continue;
      std::string have;
      for (const MeshAttribute& a : shape.attributes) have += (have.empty() ? "" : ", ") + a.name;
      throw SceneError(shape.origin + ": its material \"" + m.name + "\" reads mesh attribute \"" +
                       name + "\" (" + texture_name(scene, t) + "), which the shape does not " +
                       "have (" + (have.empty() ? "it has no attributes" : "it has " + have) +
                       ")");
    }
  }
}

}  // namespace

void check_mesh_attribute_use(const Scene& scene) {
  bool any = false;
  for (const Texture& t : scene.textures) any = any || t.kind == TextureKind::mesh_attribute;
  if (!any) return;
  for (const Material& m : scene.materials) check_no_gradient(scene, m);
  for (const Light& light : scene.lights) {
    if (is_attribute(scene, light.texture)) {
      throw SceneError("a light's " + texture_name(scene, light.texture) +
                       " is a mesh_attribute, which only a shape's material can read");
    }
  }
  for (const Shape& shape : scene.shapes) check_shape(scene, shape);
  for (const ShapeGroup& group : scene.groups) {
    for (const Shape& shape : group.shapes) check_shape(scene, shape);
  }
}

}  // namespace tessera
