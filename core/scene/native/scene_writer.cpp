#include "scene/native/scene_writer.h"

#include <charconv>
#include <cmath>
#include <glm/gtc/matrix_access.hpp>
#include <glm/matrix.hpp>
#include <set>

#include "scene/native/json_value.h"
#include "scene/native/material_parser.h"
#include "scene/native/medium_parser.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

/// Length of the valid UTF-8 sequence starting at text[i], or 0 when it is not one.
size_t utf8_sequence(std::string_view text, size_t i) {
  auto byte = [&](size_t k) { return static_cast<unsigned char>(text[k]); };
  unsigned char c = byte(i);
  size_t length = c < 0x80           ? 1
                  : (c >> 5) == 0x6  ? 2
                  : (c >> 4) == 0xe  ? 3
                  : (c >> 3) == 0x1e ? 4
                                     : 0;
  if (length == 0 || i + length > text.size()) return 0;
  for (size_t k = 1; k < length; ++k) {
    if ((byte(i + k) >> 6) != 0x2) return 0;
  }
  if (length == 2 && c < 0xc2) return 0;                          // overlong
  if (length == 3 && c == 0xe0 && byte(i + 1) < 0xa0) return 0;   // overlong
  if (length == 3 && c == 0xed && byte(i + 1) >= 0xa0) return 0;  // surrogates
  if (length == 4 && c == 0xf0 && byte(i + 1) < 0x90) return 0;   // overlong
  if (length == 4 && (c > 0xf4 || (c == 0xf4 && byte(i + 1) >= 0x90))) return 0;
  return length;
}

/// `text` with bytes that are not UTF-8 replaced by '?': JSON text is UTF-8.
std::string valid_utf8(std::string_view text) {
  std::string out;
  for (size_t i = 0; i < text.size();) {
    size_t length = utf8_sequence(text, i);
    if (length == 0) {
      out += '?';
      ++i;
    } else {
      out.append(text.substr(i, length));
      i += length;
    }
  }
  return out;
}

/// A JSON string literal of valid UTF-8 `text`.
std::string json_string(std::string_view text) {
  std::string out = "\"";
  for (char c : text) {
    auto byte = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (byte < 0x20 || byte == 0x7f) {
      static const char kHex[] = "0123456789abcdef";
      out += "\\u00";
      out += kHex[byte >> 4];
      out += kHex[byte & 15];
    } else {
      out += c;
    }
  }
  return out + "\"";
}

/// The shortest decimal that reads back as `x` (std::to_chars); -0 as "-0.0", which the JSON
/// reader takes as a double, keeping its sign (a bare "-0" reads as the integer 0).
std::string number(double x, const std::string& what) {
  if (!std::isfinite(x)) {
    throw SceneError(what + ": " + format_number(x) + " cannot be written in JSON");
  }
  if (x == 0) return std::signbit(x) ? "-0.0" : "0";
  char buffer[64];
  auto result = std::to_chars(buffer, buffer + sizeof buffer, x);
  return std::string(buffer, result.ptr);
}

std::string vec3(const glm::dvec3& v, const std::string& what) {
  return "[" + number(v.x, what) + ", " + number(v.y, what) + ", " + number(v.z, what) + "]";
}

const char* fov_axis_name(FovAxis axis) {
  switch (axis) {
    case FovAxis::x:
      return "x";
    case FovAxis::y:
      return "y";
    case FovAxis::smaller:
      return "smaller";
    case FovAxis::larger:
      return "larger";
    case FovAxis::diagonal:
      return "diagonal";
  }
  return "x";
}

std::string camera_json(const Camera& c) {
  if (c.projection == Projection::orthographic) {
    return "  \"camera\": {\n    \"type\": \"orthographic\", \"position\": " +
           vec3(c.position, "camera.position") +
           ",\n    \"look_at\": " + vec3(c.look_at, "camera.look_at") +
           ",\n    \"up\": " + vec3(c.up, "camera.up") + ",\n    \"view_size\": [" +
           number(c.view_size.x, "camera.view_size") + ", " +
           number(c.view_size.y, "camera.view_size") + "]" +
           (c.view_aspect > 0 ? ", \"view_aspect\": " + number(c.view_aspect, "camera.view_aspect") : std::string()) +
           "\n  },\n";
  }
  return "  \"camera\": {\n    \"position\": " + vec3(c.position, "camera.position") +
         ",\n    \"look_at\": " + vec3(c.look_at, "camera.look_at") +
         ",\n    \"up\": " + vec3(c.up, "camera.up") +
         ",\n    \"fov\": " + number(c.fov_deg, "camera.fov") + ", \"fov_axis\": \"" +
         fov_axis_name(c.fov_axis) +
         "\",\n    \"aperture_radius\": " + number(c.aperture_radius, "camera.aperture_radius") +
         ", \"focus_distance\": " + number(c.focus_distance, "camera.focus_distance") + "\n  },\n";
}

/// Names as written (of materials, textures, groups): valid UTF-8, non-empty and unique.
template <typename T>
std::vector<std::string> unique_names(const std::vector<T>& items, const char* fallback) {
  std::vector<std::string> names;
  std::set<std::string> used;
  for (const T& m : items) {
    std::string base = valid_utf8(m.name);
    if (base.empty()) base = fallback;
    std::string name = base;
    for (int k = 2; used.count(name); ++k) name = base + " #" + std::to_string(k);
    used.insert(name);
    names.push_back(name);
  }
  return names;
}

const char* bool_text(bool b) { return b ? "true" : "false"; }

/// The names the JSON uses for textures, materials and groups.
struct Names {
  std::vector<std::string> textures, materials, groups, media;
};

/// The JSON string naming medium `index` (-1 = none, which the caller leaves out).
std::string medium_name(int32_t index, const Names& names, const std::string& what) {
  if (index < 0 || size_t(index) >= names.media.size()) {
    throw SceneError(what + ": medium index out of range");
  }
  return json_string(names.media[size_t(index)]);
}

std::string texture_name(int32_t index, const Names& names, const std::string& what) {
  if (index < 0 || size_t(index) >= names.textures.size()) {
    throw SceneError(what + ": texture index out of range");
  }
  return json_string(names.textures[index]);
}

std::string textured_color(const TexturedColor& c, const Names& names, const std::string& what) {
  if (c.is_constant()) return vec3(c.value, what);
  return "{\"texture\": " + texture_name(c.texture, names, what) +
         ", \"scale\": " + vec3(c.value, what) + "}";
}

std::string textured_float(const TexturedFloat& f, const Names& names, const std::string& what) {
  if (f.is_constant()) return number(f.value, what);
  return "{\"texture\": " + texture_name(f.texture, names, what) +
         ", \"scale\": " + number(f.value, what) + "}";
}

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

/// A 4 x 4 matrix as {"matrix": rows}.
std::string matrix_json(const glm::dmat4& m, const std::string& what) {
  std::string out = "{\"matrix\": [";
  for (int r = 0; r < 4; ++r) {
    out += r ? ", [" : "[";
    for (int c = 0; c < 4; ++c) out += (c ? ", " : "") + number(m[c][r], what);
    out += "]";
  }
  return out + "]}";
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

std::string film_json(const Film& film) {
  std::string filter;
  switch (film.filter.kind) {
    case FilterKind::box:
      filter = "{\"type\": \"box\"}";
      break;
    case FilterKind::tent:
      filter =
          "{\"type\": \"tent\", \"radius\": " + number(film.filter.radius, "film.filter") + "}";
      break;
    case FilterKind::gaussian:
      filter = "{\"type\": \"gaussian\", \"stddev\": " + number(film.filter.stddev, "film.filter") +
               ", \"radius\": " + number(film.filter.radius, "film.filter") + "}";
      break;
    case FilterKind::mitchell:
      filter = "{\"type\": \"mitchell\", \"b\": " + number(film.filter.b, "film.filter") +
               ", \"c\": " + number(film.filter.c, "film.filter") + "}";
      break;
    case FilterKind::lanczos:
      filter = "{\"type\": \"lanczos\", \"lobes\": " + std::to_string(int(film.filter.radius)) + "}";
      break;
  }
  return "  \"film\": {\"width\": " + std::to_string(film.width) +
         ", \"height\": " + std::to_string(film.height) + ", \"filter\": " + filter + "},\n";
}

void append_points(std::string& out, const char* key, const std::vector<glm::dvec3>& points,
                   const std::string& what) {
  out += ",\n      \"";
  out += key;
  out += "\": [";
  for (size_t i = 0; i < points.size(); ++i) {
    out += i ? ",\n        " : "\n        ";
    out += vec3(points[i], what);
  }
  out += "\n      ]";
}

/// A curves shape's "control_points" ([x, y, z, radius] each) and "curve_sizes".
void append_curves(std::string& out, const Shape& s, const std::string& what) {
  uint64_t total = 0;
  for (uint32_t n : s.curve_sizes) total += n;
  if (s.curve_sizes.empty() || total != s.control_points.size()) {
    throw SceneError(what + ": the curve sizes do not add up to the control points");
  }
  out += ",\n      \"control_points\": [";
  for (size_t i = 0; i < s.control_points.size(); ++i) {
    const glm::dvec4& cp = s.control_points[i];
    out += i ? ",\n        [" : "\n        [";
    out += number(cp.x, what) + ", " + number(cp.y, what) + ", " + number(cp.z, what) + ", " +
           number(cp.w, what) + "]";
  }
  out += "\n      ],\n      \"curve_sizes\": [";
  for (size_t i = 0; i < s.curve_sizes.size(); ++i) {
    out += (i ? ", " : "") + std::to_string(s.curve_sizes[i]);
  }
  out += "]";
}

/// "attributes": {"vertex_color": [[r, g, b], ...], "face_id": [x, ...]}; nothing without any.
void append_attributes(std::string& out, const Shape& s, const std::string& what) {
  if (s.attributes.empty()) return;
  std::string problem = mesh_attributes_problem(s.attributes, s.positions.size(), s.indices.size());
  if (!problem.empty()) throw SceneError(what + ": " + problem);
  out += ",\n      \"attributes\": {";
  for (size_t k = 0; k < s.attributes.size(); ++k) {
    const MeshAttribute& a = s.attributes[k];
    out += (k ? ",\n        " : "\n        ") + json_string(valid_utf8(a.name)) + ": [";
    const size_t c = size_t(a.channels);
    for (size_t row = 0; row < a.rows(); ++row) {
      out += row ? ", " : "";
      if (c == 1) {
        out += number(a.values[row], what);
      } else {
        out += "[" + number(a.values[row * c], what) + ", " + number(a.values[row * c + 1], what) +
               ", " + number(a.values[row * c + 2], what) + "]";
      }
    }
    out += "]";
  }
  out += "\n      }";
}

/// An SDF grid's "transform" and its "file" (bundle path) or inline "resolution" and "values".
void append_sdf_grid(std::string& out, const Shape& s, const std::string& what) {
  out += ",\n      \"transform\": " + matrix_json(s.to_world, what);
  if (!s.sdf_file.empty()) {
    out += ",\n      \"file\": " + json_string(s.sdf_file);
    return;
  }
  const glm::u32vec3 r = s.sdf_resolution;
  if (uint64_t(r.x) * r.y * r.z != s.sdf_values.size()) {
    throw SceneError(what + ": the SDF grid's values do not match its resolution");
  }
  out += ",\n      \"resolution\": [" + std::to_string(r.x) + ", " + std::to_string(r.y) + ", " +
         std::to_string(r.z) + "],\n      \"values\": [";
  for (size_t i = 0; i < s.sdf_values.size(); ++i) {
    out += (i ? ", " : "") + number(double(s.sdf_values[i]), what);
  }
  out += "]";
}

std::string shape_json(const Shape& s, const std::string& what,
                       const std::vector<Material>& materials, const Names& names) {
  if (s.kind == Shape::Kind::instance) {
    if (s.group >= names.groups.size()) throw SceneError(what + ": group index out of range");
    return "    {\"type\": \"instance\", \"group\": " + json_string(names.groups[s.group]) +
           ",\n      \"transform\": " + matrix_json(s.to_world, what) + "}";
  }
  if (s.material >= materials.size()) throw SceneError(what + ": material index out of range");
  std::string out = "    {";
  if (s.kind == Shape::Kind::sphere) {
    out += "\"type\": \"sphere\", \"center\": " + vec3(s.center, what) +
           ", \"radius\": " + number(s.radius, what) +
           ", \"flip_normals\": " + (s.flip_normals ? "true" : "false");
    if (s.frame != glm::dmat3(1.0)) {
      out += ",\n      \"frame\": [" + vec3(glm::row(s.frame, 0), what) + ", " +
             vec3(glm::row(s.frame, 1), what) + ", " + vec3(glm::row(s.frame, 2), what) + "]";
    }
  } else if (s.kind == Shape::Kind::sdfgrid) {
    out += std::string("\"type\": \"sdfgrid\", \"normals\": ") +
           (s.sdf_normals == SdfNormals::smooth ? "\"smooth\"" : "\"analytic\"");
  } else if (s.kind == Shape::Kind::curves) {
    out += std::string("\"type\": \"curves\", \"basis\": ") +
           (s.curve_basis == CurveBasis::linear ? "\"linear\"" : "\"bspline\"");
  } else {
    out += "\"type\": \"triangles\"";
  }
  out += ", \"material\": " + json_string(names.materials[s.material]);
  if (s.kind == Shape::Kind::sdfgrid) {
    if (s.is_emitter()) throw SceneError(what + ": SDF grids cannot emit light");
    append_sdf_grid(out, s, what);
    return out + "}";
  }
  if (s.kind == Shape::Kind::curves) {
    if (s.is_emitter()) throw SceneError(what + ": curves cannot emit light");
    append_curves(out, s, what);
    return out + "}";
  }
  if (s.bounds_medium() && s.kind != Shape::Kind::triangles && s.kind != Shape::Kind::sphere) {
    throw SceneError(what + ": only triangles and spheres can bound a medium");
  }
  if (s.interior >= 0) out += ", \"interior\": " + medium_name(s.interior, names, what);
  if (s.exterior >= 0) out += ", \"exterior\": " + medium_name(s.exterior, names, what);
  if (s.is_emitter()) {
    out += ",\n      \"emission\": " +
           textured_color({s.emission, s.emission_texture}, names, what + ".emission");
  }
  if (s.is_emitter() && s.two_sided_emission) {
    const Material& m = materials[s.material];
    if (!m.two_sided && !is_glass_kind(m.type)) {
      throw SceneError(what +
                       ": it emits from both sides but its material is one-sided, which "
                       "the native format cannot say");
    }
    out += ", \"two_sided\": true";
  }
  if (s.kind == Shape::Kind::triangles) {
    if (s.indices.empty()) throw SceneError(what + ": no triangles");
    if (!s.normals.empty() && s.normals.size() != s.positions.size()) {
      throw SceneError(what + ": one normal per vertex is needed");
    }
    append_points(out, "vertices", s.positions, what);
    out += ",\n      \"indices\": [";
    for (size_t i = 0; i < s.indices.size(); ++i) {
      const glm::u32vec3& t = s.indices[i];
      out += i ? ",\n        [" : "\n        [";
      out += std::to_string(t.x) + ", " + std::to_string(t.y) + ", " + std::to_string(t.z) + "]";
    }
    out += "\n      ]";
    if (!s.normals.empty()) append_points(out, "normals", s.normals, what);
    if (!s.uvs.empty()) {
      if (s.uvs.size() != s.positions.size()) {
        throw SceneError(what + ": one uv per vertex is needed");
      }
      out += ",\n      \"uvs\": [";
      for (size_t i = 0; i < s.uvs.size(); ++i) {
        out += i ? ", [" : "\n        [";
        out += number(s.uvs[i].x, what) + ", " + number(s.uvs[i].y, what) + "]";
      }
      out += "\n      ]";
    }
    append_attributes(out, s, what);
  }
  return out + "}";
}

/// `items` as the body of a JSON object ("{...}") or array ("[...]"), one per line.
template <typename F>
std::string block(size_t count, char open, char close, F item) {
  std::string out(1, open);
  for (size_t i = 0; i < count; ++i) out += (i ? ",\n" : "\n") + item(i);
  out += count ? "\n  " : "";
  return out + close;
}

}  // namespace

std::string write_scene_json(const Scene& scene, const std::string& comment) {
  std::string out;
  if (!comment.empty()) out += "// " + valid_utf8(printable_whole(comment)) + "\n";
  out += "{\n  \"tessera\": 1,\n";
  Names names{unique_names(scene.textures, "texture"), unique_names(scene.materials, "material"),
              unique_names(scene.groups, "group"), unique_names(scene.media, "medium")};
  std::string camera = camera_json(scene.camera);
  if (scene.camera.medium >= 0) {
    // Before the closing "\n  },\n" of the camera object.
    camera.insert(camera.size() - 6, ", \"medium\": " + medium_name(scene.camera.medium, names, "camera.medium"));
  }
  out += camera;
  out += film_json(scene.film);
  out += "  \"render\": {\"spp\": " + std::to_string(scene.render.spp) +
         ", \"max_depth\": " + std::to_string(scene.render.max_depth) +
         ", \"rr_depth\": " + std::to_string(scene.render.rr_depth) +
         ", \"seed\": " + std::to_string(scene.render.seed) +
         ", \"hide_emitters\": " + bool_text(scene.render.hide_emitters) + "},\n";
  out += "  \"textures\": " + block(scene.textures.size(), '{', '}', [&](size_t i) {
    return texture_json(scene.textures[i], i, names);
  }) + ",\n";
  out += "  \"materials\": " + block(scene.materials.size(), '{', '}', [&](size_t i) {
    return material_json(scene.materials[i], i, names);
  }) + ",\n";
  if (!scene.media.empty()) {  // a scene without media writes as before media existed
    out += "  \"media\": " + block(scene.media.size(), '{', '}', [&](size_t i) {
      return medium_json(scene.media[i], i, names, scene.textures);
    }) + ",\n";
  }
  out += "  \"groups\": " + block(scene.groups.size(), '{', '}', [&](size_t g) {
    const ShapeGroup& group = scene.groups[g];
    std::string body = "    " + json_string(names.groups[g]) + ": {\"shapes\": [";
    for (size_t i = 0; i < group.shapes.size(); ++i) {
      const Shape& shape = group.shapes[i];
      if (shape.kind == Shape::Kind::instance) {
        throw SceneError("groups." + printable(names.groups[g]) + ": groups cannot hold instances");
      }
      body += (i ? ",\n" : "\n") +
              shape_json(shape, "groups." + printable(names.groups[g]) + ".shapes[" +
                                    std::to_string(i) + "] (" + printable(shape.origin) + ")",
                         scene.materials, names);
    }
    return body + "]}";
  }) + ",\n";
  out += "  \"shapes\": " + block(scene.shapes.size(), '[', ']', [&](size_t i) {
    const Shape& shape = scene.shapes[i];
    return shape_json(shape, "shapes[" + std::to_string(i) + "] (" + printable(shape.origin) + ")",
                      scene.materials, names);
  }) + ",\n";
  out += "  \"lights\": " + block(scene.lights.size(), '[', ']', [&](size_t i) {
    return light_json(scene.lights[i], i, names);
  }) + "\n}\n";
  return out;
}

}  // namespace tessera
