// The surface BSDFs of a Mitsuba scene (mitsuba_surface_bsdfs.h): diffuse, conductors,
// dielectrics, plastics, the principled family and the polarizer.
#include "scene/mitsuba/mitsuba_surface_bsdfs.h"

#include <algorithm>
#include <cmath>

#include "scene/message_text.h"
#include "scene/mitsuba/mitsuba_ior.h"
#include "scene/mitsuba/mitsuba_metals.h"

namespace tessera {
namespace {

constexpr MitsubaColorRole kReflectance = MitsubaColorRole::reflectance;

/// int_ior or ext_ior: a positive number, or a name from Mitsuba's table.
double read_ior(MitsubaPlugin& plugin, const std::string& name, std::string_view fallback) {
  std::string text(fallback);
  std::optional<double> ior = plugin.take_float_or_name(name, text);
  if (!ior) {
    ior = mitsuba_named_ior(text);
    if (!ior) {
      fail_at(*plugin.property(name), "unknown IOR name \"" + printable(text) +
                                          "\" (Mitsuba's names: " + mitsuba_ior_names() + ")");
    }
  }
  if (!(*ior > 0)) {
    fail_at(*plugin.property(name), "must be > 0 (got " + format_number(*ior) + ")");
  }
  return *ior;
}

/// One alpha: > 0 when constant (the smooth BSDFs are the alpha = 0 limit).
TexturedFloat read_alpha(MitsubaPlugin& plugin, std::string_view name,
                         MitsubaTextures& textures) {
  TexturedFloat alpha = read_textured_float(plugin, name, 0.1, textures);
  if (alpha.is_constant() && !(alpha.value > 0)) {
    fail_at(*plugin.property(name),
            "must be > 0 (got " + format_number(alpha.value) +
                "; for a smooth surface use the BSDF without \"rough\")");
  }
  return alpha;
}

/// distribution, alpha (or alpha_u and alpha_v when `anisotropic`) and sample_visible.
void read_microfacets(MitsubaPlugin& plugin, Material& m, MitsubaTextures& textures,
                      bool anisotropic) {
  std::optional<std::string> distribution = plugin.take_string("distribution");
  if (!distribution || *distribution == "beckmann") {
    m.distribution = MicrofacetDistribution::beckmann;
  } else if (*distribution == "ggx") {
    m.distribution = MicrofacetDistribution::ggx;
  } else {
    fail_at(*plugin.property("distribution"),
            "\"" + printable(*distribution) + "\" is no distribution (beckmann or ggx)");
  }
  if (anisotropic && (plugin.has("alpha_u") || plugin.has("alpha_v"))) {
    if (plugin.has("alpha")) {
      fail_at(plugin.element(), "give alpha or alpha_u and alpha_v, not both");
    }
    if (!plugin.has("alpha_u") || !plugin.has("alpha_v")) {
      fail_at(plugin.element(), "give both alpha_u and alpha_v (or alpha)");
    }
    m.alpha_u = read_alpha(plugin, "alpha_u", textures);
    m.alpha_v = read_alpha(plugin, "alpha_v", textures);
  } else {
    m.alpha_u = read_alpha(plugin, "alpha", textures);
    m.alpha_v = m.alpha_u;
  }
  m.sample_visible = plugin.take_boolean("sample_visible").value_or(true);
}

/// A principled weight: a <float> in [0, 1] or a texture.
TexturedFloat read_weight(MitsubaPlugin& plugin, std::string_view name, double fallback,
                          MitsubaTextures& textures) {
  TexturedFloat w = read_textured_float(plugin, name, fallback, textures);
  if (w.is_constant() && !(w.value >= 0 && w.value <= 1)) {
    fail_at(*plugin.property(name), "must be in [0, 1] (got " + format_number(w.value) + ")");
  }
  return w;
}

/// The index of principledthin and pplastic: eta as a <float> or a texture (Mitsuba reads it
/// as an unbounded texture), or int_ior / ext_ior (pplastic only; not with eta).
void read_textured_eta(MitsubaPlugin& plugin, MitsubaTextures& textures, Material& m,
                       bool ior_names) {
  if (ior_names && plugin.has("eta") && (plugin.has("int_ior") || plugin.has("ext_ior"))) {
    fail_at(plugin.element(), "give eta or int_ior and ext_ior, not both (as Mitsuba requires)");
  }
  if (!plugin.has("eta") && ior_names) {
    m.ior = read_relative_ior(plugin, "polypropylene");
    if (m.ior == 1) {
      fail_at(plugin.element(),
              "int_ior and ext_ior must differ (as Mitsuba requires)");
    }
    return;
  }
  const TexturedFloat eta = read_textured_float(plugin, "eta", 1.5, textures);
  if (eta.is_constant() && !(eta.value > 0)) {
    fail_at(*plugin.property("eta"), "must be > 0 (got " + format_number(eta.value) + ")");
  }
  m.ior = eta.value;
  m.ior_texture = eta.texture;
}

}  // namespace

double read_relative_ior(MitsubaPlugin& plugin, std::string_view interior_default) {
  double ior = read_ior(plugin, "int_ior", interior_default) / read_ior(plugin, "ext_ior", "air");
  if (!std::isfinite(ior) || !(ior > 0)) {
    fail_at(plugin.element(), "int_ior / ext_ior is not a usable index of refraction");
  }
  return ior;
}

Material read_diffuse(MitsubaPlugin& plugin, MitsubaTextures& textures) {
  Material m;
  m.type = MaterialType::diffuse;
  m.reflectance = read_textured_color(plugin, "reflectance", glm::dvec3(0.5), kReflectance,
                                      textures);
  return m;
}

Material read_conductor(MitsubaPlugin& plugin, MitsubaTextures& textures, bool rough) {
  Material m;
  std::optional<std::string> material = plugin.take_string("material");
  std::optional<glm::dvec3> eta = plugin.take_color("eta", MitsubaColorRole::unbounded);
  std::optional<glm::dvec3> k = plugin.take_color("k", MitsubaColorRole::unbounded);
  if (eta || k) {
    if (material && *material != "none") {
      fail_at(*plugin.property("material"),
              "give either eta and k or material, not both (as Mitsuba requires)");
    }
    m.eta = eta.value_or(glm::dvec3(0));
    m.k = k.value_or(glm::dvec3(1));
  } else if (!material || *material == "none") {
    m.perfect = true;  // Mitsuba's eta 0, k 1: reflectance 1 at every angle
    m.eta = glm::dvec3(0);
    m.k = glm::dvec3(1);
  } else {
    std::optional<MitsubaMetal> metal = mitsuba_named_metal(*material);
    if (!metal) {
      fail_at(*plugin.property("material"),
              "unknown conductor \"" + printable(*material) + "\" (Mitsuba's names: " +
                  mitsuba_metal_names() + ", none)");
    }
    m.eta = metal->eta;
    m.k = metal->k;
  }
  m.specular_reflectance = read_textured_color(plugin, "specular_reflectance", glm::dvec3(1),
                                               kReflectance, textures);
  if (rough) {
    m.type = MaterialType::rough_conductor;
    read_microfacets(plugin, m, textures, true);
  } else if (m.perfect && m.specular_reflectance.is_constant() &&
             m.specular_reflectance.value == glm::dvec3(1)) {
    m.type = MaterialType::mirror;
  } else {
    m.type = MaterialType::conductor;
  }
  return m;
}

Material read_dielectric(MitsubaPlugin& plugin, MitsubaTextures& textures, MaterialType type) {
  Material m;
  m.type = type;
  m.ior = read_relative_ior(plugin, "bk7");
  m.specular_reflectance = read_textured_color(plugin, "specular_reflectance", glm::dvec3(1),
                                               kReflectance, textures);
  m.specular_transmittance = read_textured_color(plugin, "specular_transmittance",
                                                 glm::dvec3(1), kReflectance, textures);
  if (type == MaterialType::rough_glass) read_microfacets(plugin, m, textures, true);
  return m;
}

Material read_plastic(MitsubaPlugin& plugin, MitsubaTextures& textures, bool rough) {
  Material m;
  m.type = rough ? MaterialType::rough_plastic : MaterialType::plastic;
  m.reflectance = read_textured_color(plugin, "diffuse_reflectance", glm::dvec3(0.5),
                                      kReflectance, textures);
  m.specular_reflectance = read_textured_color(plugin, "specular_reflectance", glm::dvec3(1),
                                               kReflectance, textures);
  m.ior = read_relative_ior(plugin, "polypropylene");
  m.nonlinear = plugin.take_boolean("nonlinear").value_or(false);
  if (rough) read_microfacets(plugin, m, textures, false);
  return m;
}

Material read_principled(MitsubaPlugin& plugin, MitsubaTextures& textures) {
  Material m;
  m.type = MaterialType::principled;
  PrincipledParameters& p = m.principled;
  m.reflectance = read_textured_color(plugin, "base_color", glm::dvec3(0.5), kReflectance, textures);
  p.roughness = read_weight(plugin, "roughness", 0.5, textures);
  p.anisotropic = read_weight(plugin, "anisotropic", 0, textures);
  p.metallic = read_weight(plugin, "metallic", 0, textures);
  p.spec_trans = read_weight(plugin, "spec_trans", 0, textures);
  p.spec_tint = read_weight(plugin, "spec_tint", 0, textures);
  p.sheen = read_weight(plugin, "sheen", 0, textures);
  p.sheen_tint = read_weight(plugin, "sheen_tint", 0, textures);
  p.flatness = read_weight(plugin, "flatness", 0, textures);
  p.clearcoat = read_weight(plugin, "clearcoat", 0, textures);
  p.clearcoat_gloss = read_weight(plugin, "clearcoat_gloss", 0, textures);
  const std::pair<const char*, double*> rates[] = {
      {"main_specular_sampling_rate", &p.main_specular_sampling_rate},
      {"clearcoat_sampling_rate", &p.clearcoat_sampling_rate},
      {"diffuse_reflectance_sampling_rate", &p.diffuse_reflectance_sampling_rate},
  };
  for (const auto& [name, rate] : rates) {
    *rate = plugin.take_float(name).value_or(1.0);
    if (!(*rate >= 0)) {
      fail_at(*plugin.property(name), "must be >= 0 (got " + format_number(*rate) + ")");
    }
  }
  if (plugin.has("eta") && plugin.has("specular")) {
    fail_at(plugin.element(), "give eta or specular, not both (as Mitsuba requires)");
  }
  // Mitsuba moves eta = 1 (and specular = 0) off the values transmission cannot use.
  if (std::optional<double> eta = plugin.take_float("eta")) {
    if (!(*eta > 0)) fail_at(*plugin.property("eta"), "must be > 0 (got " + format_number(*eta) + ")");
    m.ior = p.transmits() && *eta == 1 ? 1.001 : *eta;
  } else {
    double specular = plugin.take_float("specular").value_or(0.5);
    if (!(specular >= 0 && specular < 12.5)) {
      fail_at(*plugin.property("specular"),
              "must be in [0, 12.5) (got " + format_number(specular) + ")");
    }
    if (p.transmits() && specular == 0) specular = 1e-3;
    // Mitsuba's conversion, in float as there: eta = 2 / (1 - sqrt(0.08 specular)) - 1.
    const float s = float(specular);
    m.ior = double(2.0f / (1.0f - std::sqrt(0.08f * s)) - 1.0f);
  }
  return m;
}

Material read_principled_thin(MitsubaPlugin& plugin, MitsubaTextures& textures) {
  Material m;
  m.type = MaterialType::principled_thin;
  PrincipledParameters& p = m.principled;
  m.reflectance = read_textured_color(plugin, "base_color", glm::dvec3(0.5), kReflectance, textures);
  p.roughness = read_weight(plugin, "roughness", 0.5, textures);
  p.anisotropic = read_weight(plugin, "anisotropic", 0, textures);
  p.spec_trans = read_weight(plugin, "spec_trans", 0, textures);
  p.spec_tint = read_weight(plugin, "spec_tint", 0, textures);
  p.sheen = read_weight(plugin, "sheen", 0, textures);
  p.sheen_tint = read_weight(plugin, "sheen_tint", 0, textures);
  p.flatness = read_weight(plugin, "flatness", 0, textures);
  p.diff_trans = read_textured_float(plugin, "diff_trans", 0, textures);
  if (p.diff_trans.is_constant() && !(p.diff_trans.value >= 0 && p.diff_trans.value <= 2)) {
    fail_at(*plugin.property("diff_trans"),
            "must be in [0, 2] (got " + format_number(p.diff_trans.value) + ")");
  }
  const std::pair<const char*, double*> rates[] = {
      {"diffuse_reflectance_sampling_rate", &p.diffuse_reflectance_sampling_rate},
      {"specular_reflectance_sampling_rate", &p.specular_reflectance_sampling_rate},
      {"specular_transmittance_sampling_rate", &p.specular_transmittance_sampling_rate},
      {"diffuse_transmittance_sampling_rate", &p.diffuse_transmittance_sampling_rate},
  };
  for (const auto& [name, rate] : rates) {
    *rate = plugin.take_float(name).value_or(1.0);
    if (!(*rate >= 0)) {
      fail_at(*plugin.property(name), "must be >= 0 (got " + format_number(*rate) + ")");
    }
  }
  read_textured_eta(plugin, textures, m, /*ior_names=*/false);
  return m;
}

Material read_pplastic(MitsubaPlugin& plugin, MitsubaTextures& textures) {
  Material m;
  m.type = MaterialType::pplastic;
  m.reflectance = read_textured_color(plugin, "diffuse_reflectance", glm::dvec3(0.5),
                                      kReflectance, textures);
  m.specular_reflectance = read_textured_color(plugin, "specular_reflectance", glm::dvec3(1),
                                               kReflectance, textures);
  read_textured_eta(plugin, textures, m, /*ior_names=*/true);
  read_microfacets(plugin, m, textures, /*anisotropic=*/true);
  return m;
}

Material read_polarizer(MitsubaPlugin& plugin, MitsubaTextures& textures) {
  Material m;
  m.type = MaterialType::polarizer;
  m.specular_transmittance =
      read_textured_color(plugin, "transmittance", glm::dvec3(1), kReflectance, textures);
  if (!plugin.take_named_object("theta")) plugin.ignore("theta");
  plugin.take_boolean("polarizing");
  return m;
}

}  // namespace tessera
