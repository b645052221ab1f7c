#include "scene/native/scene_writer_materials.h"

#include "scene/native/json_value.h"
#include "scene/native/material_parser.h"
#include "scene/native/medium_parser.h"
#include "scene/scene_error.h"

namespace tessera::scene_writer {

namespace {

const char* material_type_name(MaterialType type) {
  switch (type) {
    case MaterialType::diffuse: return "diffuse";
    case MaterialType::mirror: return "mirror";
    case MaterialType::glass: return "glass";
    case MaterialType::conductor: return "conductor";
    case MaterialType::rough_conductor: return "rough_conductor";
    case MaterialType::rough_glass: return "rough_glass";
    case MaterialType::thin_glass: return "thin_glass";
    case MaterialType::plastic: return "plastic";
    case MaterialType::rough_plastic: return "rough_plastic";
    case MaterialType::principled: return "principled";
    case MaterialType::blend: return "blend";
    case MaterialType::principled_thin: return "principled_thin";
    case MaterialType::pplastic: return "pplastic";
    case MaterialType::polarizer: return "polarizer";
    case MaterialType::hair: return "hair";
  }
  return "diffuse";
}

/// The keys of a principled material, every one written.
std::string principled_keys(const Material& m, const Names& names, const std::string& what) {
  const PrincipledParameters& p = m.principled;
  const std::pair<const char*, const TexturedFloat*> weights[] = {
      {"roughness", &p.roughness},   {"anisotropic", &p.anisotropic},
      {"metallic", &p.metallic},     {"spec_trans", &p.spec_trans},
      {"spec_tint", &p.spec_tint},   {"sheen", &p.sheen},
      {"sheen_tint", &p.sheen_tint}, {"flatness", &p.flatness},
      {"clearcoat", &p.clearcoat},   {"clearcoat_gloss", &p.clearcoat_gloss},
  };
  std::string out = ", \"base_color\": " + textured_color(m.reflectance, names, what + ".base_color");
  for (const auto& [key, value] : weights) {
    out += std::string(", \"") + key + "\": " + textured_float(*value, names, what + "." + key);
  }
  out += ", \"ior\": " + number(m.ior, what + ".ior");
  out += ", \"main_specular_sampling_rate\": " +
         number(p.main_specular_sampling_rate, what + ".main_specular_sampling_rate");
  out += ", \"clearcoat_sampling_rate\": " +
         number(p.clearcoat_sampling_rate, what + ".clearcoat_sampling_rate");
  out += ", \"diffuse_reflectance_sampling_rate\": " +
         number(p.diffuse_reflectance_sampling_rate, what + ".diffuse_reflectance_sampling_rate");
  return out;
}

/// The index: a number, or a texture for the two types whose index Mitsuba lets one give.
std::string ior_json(const Material& m, const Names& names, const std::string& what) {
  return textured_float(TexturedFloat{m.ior, m.ior_texture}, names, what + ".ior");
}

/// The keys of a principled_thin material, every one written.
std::string principled_thin_keys(const Material& m, const Names& names, const std::string& what) {
  const PrincipledParameters& p = m.principled;
  const std::pair<const char*, const TexturedFloat*> weights[] = {
      {"roughness", &p.roughness}, {"anisotropic", &p.anisotropic}, {"spec_trans", &p.spec_trans},
      {"spec_tint", &p.spec_tint}, {"sheen", &p.sheen},             {"sheen_tint", &p.sheen_tint},
      {"flatness", &p.flatness},   {"diff_trans", &p.diff_trans},
  };
  const std::pair<const char*, double> rates[] = {
      {"diffuse_reflectance_sampling_rate", p.diffuse_reflectance_sampling_rate},
      {"specular_reflectance_sampling_rate", p.specular_reflectance_sampling_rate},
      {"specular_transmittance_sampling_rate", p.specular_transmittance_sampling_rate},
      {"diffuse_transmittance_sampling_rate", p.diffuse_transmittance_sampling_rate},
  };
  std::string out = ", \"base_color\": " + textured_color(m.reflectance, names, what + ".base_color");
  for (const auto& [key, value] : weights) {
    out += std::string(", \"") + key + "\": " + textured_float(*value, names, what + "." + key);
  }
  out += ", \"ior\": " + ior_json(m, names, what);
  for (const auto& [key, rate] : rates) {
    out += std::string(", \"") + key + "\": " + number(rate, what + "." + key);
  }
  return out;
}

/// The keys of `m`'s type, every one written.
std::string material_type_keys(const Material& m, const Names& names, const std::string& what) {
  MaterialType t = m.type;
  bool glass = is_glass_kind(t);
  bool plastic = t == MaterialType::plastic || t == MaterialType::rough_plastic;
  bool conductor = t == MaterialType::conductor || t == MaterialType::rough_conductor;
  bool rough = t == MaterialType::rough_conductor || t == MaterialType::rough_glass ||
               t == MaterialType::rough_plastic || t == MaterialType::pplastic;
  std::string out;
  if (t == MaterialType::principled_thin) return principled_thin_keys(m, names, what);
  if (t == MaterialType::hair) {
    const HairParameters& h = m.hair;
    return ", \"sigma_a\": " + textured_color(h.sigma_a, names, what + ".sigma_a") +
           ", \"ior\": " + number(m.ior, what + ".ior") + ", \"longitudinal_roughness\": " +
           number(h.longitudinal_roughness, what + ".longitudinal_roughness") +
           ", \"azimuthal_roughness\": " +
           number(h.azimuthal_roughness, what + ".azimuthal_roughness") +
           ", \"scale_tilt\": " + number(h.scale_tilt_deg, what + ".scale_tilt");
  }
  if (t == MaterialType::polarizer) {
    return ", \"transmittance\": " +
           textured_color(m.specular_transmittance, names, what + ".transmittance");
  }
  if (t == MaterialType::pplastic) {
    out += ", \"diffuse_reflectance\": " +
           textured_color(m.reflectance, names, what + ".diffuse_reflectance") +
           ", \"ior\": " + ior_json(m, names, what);
  }
  if (t == MaterialType::diffuse) {
    out += ", \"reflectance\": " + textured_color(m.reflectance, names, what + ".reflectance");
  }
  if (plastic) {
    out += ", \"diffuse_reflectance\": " +
           textured_color(m.reflectance, names, what + ".diffuse_reflectance") +
           ", \"nonlinear\": " + bool_text(m.nonlinear);
  }
  if (t == MaterialType::principled) return out + principled_keys(m, names, what);
  if (t != MaterialType::diffuse && t != MaterialType::mirror) {
    out += ", \"specular_reflectance\": " +
           textured_color(m.specular_reflectance, names, what + ".specular_reflectance");
  }
  if (glass) {
    out += ", \"specular_transmittance\": " +
           textured_color(m.specular_transmittance, names, what + ".specular_transmittance");
  }
  if (glass || plastic) out += ", \"ior\": " + number(m.ior, what + ".ior");
  if (conductor) {
    out += ", \"eta\": " + vec3(m.eta, what + ".eta") + ", \"k\": " + vec3(m.k, what + ".k") +
           ", \"perfect\": " + bool_text(m.perfect);
  }
  if (rough) {
    out += std::string(", \"distribution\": \"") +
           (m.distribution == MicrofacetDistribution::ggx ? "ggx" : "beckmann") + "\"";
    if (t == MaterialType::rough_plastic) {
      if (m.alpha_u.value != m.alpha_v.value || m.alpha_u.texture != m.alpha_v.texture) {
        throw SceneError(what + ": a rough plastic is isotropic (alpha_u must equal alpha_v)");
      }
      out += ", \"alpha\": " + textured_float(m.alpha_u, names, what + ".alpha");
    } else {
      out += ", \"alpha_u\": " + textured_float(m.alpha_u, names, what + ".alpha_u") +
             ", \"alpha_v\": " + textured_float(m.alpha_v, names, what + ".alpha_v");
    }
    out += std::string(", \"sample_visible\": ") + bool_text(m.sample_visible);
  }
  return out;
}

std::string material_body(const Material& m, const Names& names, const std::string& what);

/// A blend's weight and nested materials.
std::string blend_keys(const Material& m, const Names& names, const std::string& what) {
  if (m.blend.size() != 2) throw SceneError(what + ": a blend has two nested materials");
  std::string out = ", \"weight\": " + textured_float(m.blend_weight, names, what + ".weight");
  out += ", \"materials\": [";
  for (size_t i = 0; i < 2; ++i) {
    const Material& n = m.blend[i];
    const std::string where = what + ".materials[" + std::to_string(i) + "]";
    if (n.two_sided || n.back >= 0 || !n.opacity.is_constant() || n.opacity.value != 1 ||
        n.normal_map >= 0 || n.bump_map >= 0) {
      throw SceneError(where + ": a blend's nested material has no sidedness, mask or map of its own");
    }
    out += (i ? ", {" : "{") + material_body(n, names, where) + "}";
  }
  return out + "]";
}

/// "type" and the keys of m's type.
std::string material_body(const Material& m, const Names& names, const std::string& what) {
  std::string body = std::string("\"type\": \"") + material_type_name(m.type) + "\"";
  if (m.type == MaterialType::blend) return body + blend_keys(m, names, what);
  return body + material_type_keys(m, names, what);
}

/// A volume texture's keys after '{': a file with its transform, filter and wrap, or a value.
std::string volume_json(const Texture& t, const std::string& what) {
  if (t.to_uv != glm::dmat3(1.0)) throw SceneError(what + ": a volume has no to_uv");
  if (t.file.empty()) {
    if (t.channels == 1 && (t.value.y != t.value.x || t.value.z != t.value.x)) {
      throw SceneError(what + ": a one-channel constant volume holds one value");
    }
    return "\"type\": \"volume\", \"value\": " +
           (t.channels == 1 ? number(t.value.x, what) : vec3(t.value, what)) +
           (t.volume_to_world != glm::dmat4(1.0) ? ", \"transform\": " + matrix_json(t.volume_to_world, what)
                                                 : std::string());
  }
  std::string out = "\"type\": \"volume\", \"file\": " + json_string(valid_utf8(t.file));
  if (t.volume_to_world != glm::dmat4(1.0)) {
    out += ", \"transform\": " + matrix_json(t.volume_to_world, what);
  }
  return out + ", \"filter\": \"" +
         (t.filter == TextureFilter::bilinear ? "trilinear" : "nearest") + "\", \"wrap\": \"" +
         (t.wrap == TextureWrap::repeat   ? "repeat"
          : t.wrap == TextureWrap::mirror ? "mirror"
                                          : "clamp") +
         "\"";
}

}  // namespace

std::string material_json(const Material& m, size_t index, const Names& names) {
  const std::string& name = names.materials[index];
  std::string what = "materials." + printable(name);
  std::string body = material_body(m, names, what);
  if (!is_glass_kind(m.type) && m.type != MaterialType::principled_thin &&
      m.type != MaterialType::polarizer && m.type != MaterialType::hair &&
      !(m.two_sided && m.transmits())) {
    body += std::string(", \"two_sided\": ") + bool_text(m.two_sided);
  }
  if (!m.opacity.is_constant() || m.opacity.value != 1) {
    body += ", \"opacity\": " + textured_float(m.opacity, names, what + ".opacity");
  }
  if (m.normal_map >= 0) body += ", \"normal_map\": " + texture_name(m.normal_map, names, what);
  if (m.bump_map >= 0) {
    body += ", \"bump_map\": " + texture_name(m.bump_map, names, what) +
            ", \"bump_scale\": " + number(m.bump_scale, what + ".bump_scale");
  }
  if (m.back >= 0) {
    if (size_t(m.back) >= names.materials.size()) throw SceneError(what + ": back out of range");
    body += ", \"back\": " + json_string(names.materials[m.back]);
  }
  return "    " + json_string(name) + ": {" + body + "}";
}

std::string texture_json(const Texture& t, size_t index, const Names& names) {
  const std::string& name = names.textures[index];
  std::string what = "textures." + printable(name);
  std::string out = "    " + json_string(name) + ": {";
  if (t.kind == TextureKind::bitmap) {
    out += "\"type\": \"bitmap\", \"file\": " + json_string(valid_utf8(t.file)) +
           ", \"color_space\": \"" +
           (t.color_space == TextureColorSpace::srgb ? "srgb" : "linear") + "\", \"filter\": \"" +
           (t.filter == TextureFilter::bilinear ? "bilinear" : "nearest") + "\", \"wrap\": \"" +
           (t.wrap == TextureWrap::repeat   ? "repeat"
            : t.wrap == TextureWrap::mirror ? "mirror"
                                            : "clamp") +
           "\"";
  } else if (t.kind == TextureKind::rawconstant) {
    if (t.channels == 1 && (t.value.y != t.value.x || t.value.z != t.value.x)) {
      throw SceneError(what + ": a one-channel rawconstant holds one value");
    }
    if (t.to_uv != glm::dmat3(1.0)) throw SceneError(what + ": a rawconstant has no to_uv");
    return out + "\"type\": \"rawconstant\", \"value\": " +
           (t.channels == 1 ? number(t.value.x, what) : vec3(t.value, what)) + "}";
  } else if (t.kind == TextureKind::volume) {
    return out + volume_json(t, what) + "}";
  } else if (t.kind == TextureKind::mesh_attribute) {
    if (t.to_uv != glm::dmat3(1.0)) throw SceneError(what + ": a mesh_attribute has no to_uv");
    return out + "\"type\": \"mesh_attribute\", \"attribute\": " +
           json_string(valid_utf8(t.attribute)) + ", \"scale\": " + number(t.scale, what) + "}";
  } else {
    out += "\"type\": \"checkerboard\", \"color0\": " + vec3(t.color0, what) +
           ", \"color1\": " + vec3(t.color1, what);
  }
  if (t.to_uv != glm::dmat3(1.0)) {
    if (t.to_uv[0][2] != 0 || t.to_uv[1][2] != 0 || t.to_uv[2][2] != 1) {
      throw SceneError(what + ": to_uv must be affine (last row 0 0 1)");
    }
    out += ", \"to_uv\": [";
    for (int r = 0; r < 2; ++r) {
      out += r ? ", [" : "[";
      for (int c = 0; c < 3; ++c) out += (c ? ", " : "") + number(t.to_uv[c][r], what);
      out += "]";
    }
    out += "]";
  }
  return out + "}";
}

std::string medium_json(const Medium& m, size_t index, const Names& names,
                        const std::vector<Texture>& textures) {
  const std::string& name = names.media[index];
  std::string what = "media." + printable(name);
  std::string problem = medium_problem(m, &textures);
  if (!problem.empty()) throw SceneError(what + ": " + problem);
  std::string out = "    " + json_string(name) + ": {\"type\": \"" +
                    (m.kind == MediumKind::homogeneous ? "homogeneous" : "heterogeneous") +
                    "\", \"sigma_t\": " + textured_color(m.sigma_t, names, what + ".sigma_t") +
                    ", \"albedo\": " + textured_color(m.albedo, names, what + ".albedo") +
                    ", \"scale\": " + number(m.scale, what) + ",\n      \"phase\": ";
  out += m.phase == PhaseKind::isotropic ? std::string("{\"type\": \"isotropic\"}")
                                         : "{\"type\": \"hg\", \"g\": " + number(m.g, what) + "}";
  return out + ", \"sample_emitters\": " + bool_text(m.sample_emitters) + "}";
}

}  // namespace tessera::scene_writer
