#include "material.h"

namespace tessera {
namespace {

RenderColor color(const TexturedColor& c) { return {glm::vec3(c.value), c.texture}; }
RenderFloat scalar(const TexturedFloat& f) { return {float(f.value), f.texture}; }

}  // namespace

RenderMaterial make_render_material(const Material& m) {
  RenderMaterial r;
  r.type = m.type;
  r.albedo = glm::vec3(m.reflectance.value);
  r.ior = float(m.ior);
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
  r.textured = m.reflectance.texture >= 0 || m.specular_reflectance.texture >= 0 ||
               m.specular_transmittance.texture >= 0 || m.alpha_u.texture >= 0 ||
               m.alpha_v.texture >= 0 || m.opacity.texture >= 0 || m.normal_map >= 0 ||
               m.bump_map >= 0;
  return r;
}

}  // namespace tessera
