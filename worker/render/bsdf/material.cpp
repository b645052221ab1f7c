#include "render/bsdf/material.h"

#include "render/bsdf/rough_plastic_tables.h"
#include "render/texture/texture_set.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

RenderColor color(const TexturedColor& c) { return {glm::vec3(c.value), c.texture}; }
RenderFloat scalar(const TexturedFloat& f) { return {float(f.value), f.texture}; }

}  // namespace

RenderMaterial make_render_material(const Material& m, RoughPlasticTables& tables) {
  RenderMaterial r;
  r.type = m.type;
  r.albedo = glm::vec3(m.reflectance.value);
  r.ior = float(m.ior);
  r.ior_texture = m.ior_texture;
  r.two_sided = m.two_sided;
  r.reflectance = color(m.reflectance);
  r.specular_reflectance = color(m.specular_reflectance);
  r.specular_transmittance = color(m.specular_transmittance);
  r.conductor_eta = glm::vec3(m.eta);
  r.conductor_k = glm::vec3(m.k);
  r.perfect = m.perfect || m.type == MaterialType::mirror;
  r.distribution = m.distribution;
  r.alpha_u = scalar(m.alpha_u);
  r.alpha_v = scalar(m.alpha_v);
  r.sample_visible = m.sample_visible;
  r.nonlinear = m.nonlinear;
  r.back = m.back;
  r.opacity = scalar(m.opacity);
  r.normal_map = m.normal_map;
  r.bump_map = m.bump_map;
  r.bump_scale = float(m.bump_scale);
  const PrincipledParameters& pp = m.principled;
  RenderPrincipled& rp = r.principled;
  rp.roughness = scalar(pp.roughness);
  rp.anisotropic = scalar(pp.anisotropic);
  rp.metallic = scalar(pp.metallic);
  rp.spec_trans = scalar(pp.spec_trans);
  rp.spec_tint = scalar(pp.spec_tint);
  rp.sheen = scalar(pp.sheen);
  rp.sheen_tint = scalar(pp.sheen_tint);
  rp.flatness = scalar(pp.flatness);
  rp.clearcoat = scalar(pp.clearcoat);
  rp.clearcoat_gloss = scalar(pp.clearcoat_gloss);
  rp.diff_trans = scalar(pp.diff_trans);
  rp.specular_reflectance_sampling_rate = float(pp.specular_reflectance_sampling_rate);
  rp.specular_transmittance_sampling_rate = float(pp.specular_transmittance_sampling_rate);
  rp.diffuse_transmittance_sampling_rate = float(pp.diffuse_transmittance_sampling_rate);
  rp.main_specular_sampling_rate = float(pp.main_specular_sampling_rate);
  rp.clearcoat_sampling_rate = float(pp.clearcoat_sampling_rate);
  rp.diffuse_reflectance_sampling_rate = float(pp.diffuse_reflectance_sampling_rate);
  rp.transmits = m.type == MaterialType::principled && pp.transmits();
  r.blend_weight = scalar(m.blend_weight);
  r.hair = {color(m.hair.sigma_a), float(m.hair.longitudinal_roughness),
            float(m.hair.azimuthal_roughness), float(m.hair.scale_tilt_deg)};
  for (const Material& nested : m.blend) {
    r.blend.push_back(make_render_material(nested, tables));
    r.textured = r.textured || r.blend.back().textured;
  }
  if (m.type == MaterialType::rough_plastic) {
    if (!m.alpha_u.is_constant() || m.alpha_u.value != m.alpha_v.value) {
      throw SceneError("material \"" + m.name + "\": a rough plastic's alpha is one constant " +
                       "(Mitsuba's roughplastic is isotropic and untextured)");
    }
    r.rough_plastic = tables.get(m.distribution, float(m.alpha_u.value), float(m.ior));
  }
  r.textured = r.textured || m.reflectance.texture >= 0 || m.specular_reflectance.texture >= 0 ||
               m.specular_transmittance.texture >= 0 || m.alpha_u.texture >= 0 ||
               m.alpha_v.texture >= 0 || m.opacity.texture >= 0 || m.normal_map >= 0 ||
               m.bump_map >= 0 || m.ior_texture >= 0 || m.blend_weight.texture >= 0 ||
               (m.type == MaterialType::hair && m.hair.sigma_a.texture >= 0) ||
               ((m.type == MaterialType::principled || m.type == MaterialType::principled_thin) &&
                pp.textured());
  return r;
}

BsdfParams bsdf_params(const RenderMaterial& m, const TextureSet& textures, const TexturePoint& at) {
  BsdfParams p;
  p.type = m.type;
  auto color = [&](const RenderColor& c) {
    return c.texture < 0 ? c.value : c.value * textures.lookup(c.texture, at);
  };
  auto scalar = [&](const RenderFloat& f) {
    return f.texture < 0 ? f.value : f.value * textures.lookup_1(f.texture, at);
  };
  p.reflectance = color(m.reflectance);  // not clamped: Mitsuba does not clamp texels either
  p.specular_reflectance = color(m.specular_reflectance);
  p.specular_transmittance = color(m.specular_transmittance);
  p.eta = m.ior_texture < 0 ? m.ior : m.ior * textures.lookup_1(m.ior_texture, at);
  p.conductor_eta = m.conductor_eta;
  p.conductor_k = m.conductor_k;
  p.perfect = m.perfect;
  p.distribution = m.distribution;
  p.alpha_u = scalar(m.alpha_u);
  p.alpha_v = scalar(m.alpha_v);
  p.sample_visible = m.sample_visible;
  p.nonlinear = m.nonlinear;
  p.rough_plastic = m.rough_plastic;
  if (m.type == MaterialType::principled || m.type == MaterialType::principled_thin) {
    const RenderPrincipled& rp = m.principled;
    PrincipledInputs& in = p.principled;
    in.roughness = scalar(rp.roughness);
    in.anisotropic = scalar(rp.anisotropic);
    in.metallic = scalar(rp.metallic);
    in.spec_trans = scalar(rp.spec_trans);
    in.spec_tint = scalar(rp.spec_tint);
    in.sheen = scalar(rp.sheen);
    in.sheen_tint = scalar(rp.sheen_tint);
    in.flatness = scalar(rp.flatness);
    in.clearcoat = scalar(rp.clearcoat);
    in.clearcoat_gloss = scalar(rp.clearcoat_gloss);
    in.main_specular_sampling_rate = rp.main_specular_sampling_rate;
    in.clearcoat_sampling_rate = rp.clearcoat_sampling_rate;
    in.diffuse_reflectance_sampling_rate = rp.diffuse_reflectance_sampling_rate;
    in.transmits = rp.transmits;
    in.diff_trans = scalar(rp.diff_trans);
    in.specular_reflectance_sampling_rate = rp.specular_reflectance_sampling_rate;
    in.specular_transmittance_sampling_rate = rp.specular_transmittance_sampling_rate;
    in.diffuse_transmittance_sampling_rate = rp.diffuse_transmittance_sampling_rate;
  }
  if (m.type == MaterialType::hair) {
    p.hair = {color(m.hair.sigma_a), m.ior, m.hair.longitudinal_roughness,
              m.hair.azimuthal_roughness, m.hair.scale_tilt_deg};
  }
  if (m.type == MaterialType::blend) {
    p.blend_weight = scalar(m.blend_weight);
    for (const RenderMaterial& nested : m.blend) p.blend.push_back(bsdf_params(nested, textures, at));
  }
  return p;
}

}  // namespace tessera
