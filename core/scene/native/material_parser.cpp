#include "scene/native/material_parser.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "scene/native/hair_material.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

constexpr std::pair<const char*, MaterialType> kTypes[] = {
    {"diffuse", MaterialType::diffuse},
    {"mirror", MaterialType::mirror},
    {"glass", MaterialType::glass},
    {"conductor", MaterialType::conductor},
    {"rough_conductor", MaterialType::rough_conductor},
    {"rough_glass", MaterialType::rough_glass},
    {"thin_glass", MaterialType::thin_glass},
    {"plastic", MaterialType::plastic},
    {"rough_plastic", MaterialType::rough_plastic},
    {"principled", MaterialType::principled},
    {"blend", MaterialType::blend},
    {"principled_thin", MaterialType::principled_thin},
    {"pplastic", MaterialType::pplastic},
    {"polarizer", MaterialType::polarizer},
    {"hair", MaterialType::hair},
};

/// The principled material's weights (each in [0, 1], constant or textured), in the order the
/// writer writes them.
struct PrincipledKey {
  const char* key;
  TexturedFloat PrincipledParameters::*member;
};
/// The weights of principled_thin in [0, 1] (diff_trans, in [0, 2], apart).
constexpr PrincipledKey kThinWeights[] = {
    {"roughness", &PrincipledParameters::roughness},
    {"anisotropic", &PrincipledParameters::anisotropic},
    {"spec_trans", &PrincipledParameters::spec_trans},
    {"spec_tint", &PrincipledParameters::spec_tint},
    {"sheen", &PrincipledParameters::sheen},
    {"sheen_tint", &PrincipledParameters::sheen_tint},
    {"flatness", &PrincipledParameters::flatness},
};
constexpr std::pair<const char*, double PrincipledParameters::*> kThinRates[] = {
    {"diffuse_reflectance_sampling_rate", &PrincipledParameters::diffuse_reflectance_sampling_rate},
    {"specular_reflectance_sampling_rate", &PrincipledParameters::specular_reflectance_sampling_rate},
    {"specular_transmittance_sampling_rate",
     &PrincipledParameters::specular_transmittance_sampling_rate},
    {"diffuse_transmittance_sampling_rate",
     &PrincipledParameters::diffuse_transmittance_sampling_rate},
};
constexpr PrincipledKey kPrincipledWeights[] = {
    {"roughness", &PrincipledParameters::roughness},
    {"anisotropic", &PrincipledParameters::anisotropic},
    {"metallic", &PrincipledParameters::metallic},
    {"spec_trans", &PrincipledParameters::spec_trans},
    {"spec_tint", &PrincipledParameters::spec_tint},
    {"sheen", &PrincipledParameters::sheen},
    {"sheen_tint", &PrincipledParameters::sheen_tint},
    {"flatness", &PrincipledParameters::flatness},
    {"clearcoat", &PrincipledParameters::clearcoat},
    {"clearcoat_gloss", &PrincipledParameters::clearcoat_gloss},
};
constexpr std::pair<const char*, double PrincipledParameters::*> kPrincipledRates[] = {
    {"main_specular_sampling_rate", &PrincipledParameters::main_specular_sampling_rate},
    {"clearcoat_sampling_rate", &PrincipledParameters::clearcoat_sampling_rate},
    {"diffuse_reflectance_sampling_rate", &PrincipledParameters::diffuse_reflectance_sampling_rate},
};

MaterialType parse_type(const JsonValue& value) {
  std::optional<JsonValue> type = value.find("type");
  if (!type) return MaterialType::diffuse;
  const std::string& name = type->string();
  for (const auto& [text, kind] : kTypes) {
    if (name == text) return kind;
  }
  type->fail("unknown material type \"" + printable(name) +
             "\" (expected diffuse, mirror, glass, conductor, rough_conductor, rough_glass, "
             "thin_glass, plastic, rough_plastic, pplastic, principled, principled_thin, polarizer, "
             "hair or blend)");
}

bool is_rough(MaterialType t) {
  return t == MaterialType::rough_conductor || t == MaterialType::rough_glass ||
         t == MaterialType::rough_plastic || t == MaterialType::pplastic;
}
bool is_conductor(MaterialType t) {
  return t == MaterialType::conductor || t == MaterialType::rough_conductor;
}
bool is_plastic(MaterialType t) {
  return t == MaterialType::plastic || t == MaterialType::rough_plastic;
}

/// Both sides alike by nature, as glass: no two_sided key.
bool always_two_sided(MaterialType t) {
  return is_glass_kind(t) || t == MaterialType::principled_thin || t == MaterialType::polarizer ||
         t == MaterialType::hair;
}
bool has_ior(MaterialType t) {
  return is_glass_kind(t) || is_plastic(t) || t == MaterialType::principled ||
         t == MaterialType::principled_thin || t == MaterialType::pplastic;
}

/// The keys of each type, besides those every material has.
std::vector<std::string_view> keys_of(MaterialType type) {
  std::vector<std::string_view> keys = {"type"};
  if (type == MaterialType::principled_thin) {
    keys.insert(keys.end(), {"base_color", "ior", "diff_trans"});
    for (const PrincipledKey& k : kThinWeights) keys.push_back(k.key);
    for (const auto& [key, member] : kThinRates) keys.push_back(key);
    keys.insert(keys.end(), {"opacity", "normal_map", "bump_map", "bump_scale", "back"});
    return keys;
  }
  if (type == MaterialType::hair) return hair_material_keys();
  if (type == MaterialType::polarizer) {
    return {"type", "transmittance", "opacity", "normal_map", "bump_map", "bump_scale", "back"};
  }
  if (type == MaterialType::pplastic) keys.push_back("diffuse_reflectance");
  if (type == MaterialType::diffuse) keys.push_back("reflectance");
  if (is_plastic(type)) keys.insert(keys.end(), {"diffuse_reflectance", "nonlinear"});
  if (type == MaterialType::blend) return {"type", "weight", "materials", "two_sided", "opacity",
                                           "normal_map", "bump_map", "bump_scale", "back"};
  if (type != MaterialType::diffuse && type != MaterialType::mirror) {
    keys.push_back("specular_reflectance");
  }
  if (is_glass_kind(type)) keys.push_back("specular_transmittance");
  if (has_ior(type)) keys.push_back("ior");
  if (type == MaterialType::principled) {
    keys.erase(std::find(keys.begin(), keys.end(), "specular_reflectance"));
    keys.push_back("base_color");
    for (const PrincipledKey& k : kPrincipledWeights) keys.push_back(k.key);
    for (const auto& [key, member] : kPrincipledRates) keys.push_back(key);
  }
  if (is_conductor(type)) keys.insert(keys.end(), {"eta", "k", "perfect"});
  if (is_rough(type)) {
    keys.insert(keys.end(), {"distribution", "alpha", "sample_visible"});
    if (type != MaterialType::rough_plastic) keys.insert(keys.end(), {"alpha_u", "alpha_v"});
  }
  if (!always_two_sided(type)) keys.push_back("two_sided");
  keys.insert(keys.end(), {"opacity", "normal_map", "bump_map", "bump_scale", "back"});
  return keys;
}

/// Keys that belong to other types get a message saying whose they are.
void refuse_foreign_keys(const JsonValue& value, MaterialType type) {
  auto refuse = [&](const char* key, const char* message) {
    if (std::optional<JsonValue> v = value.find(key)) v->fail(message);
  };
  const bool principled_kind =
      type == MaterialType::principled || type == MaterialType::principled_thin;
  if (!has_ior(type) && type != MaterialType::hair) {
    refuse("ior", "only glass kinds, plastics, principled materials and hair have an ior");
  }
  if (!principled_kind) {
    refuse("base_color", "only principled materials have a base_color");
  }
  if (type != MaterialType::diffuse) {
    refuse("reflectance", is_plastic(type) || type == MaterialType::pplastic
                              ? "plastics call it diffuse_reflectance"
                          : principled_kind ? "principled materials call it base_color"
                                            : "only diffuse materials have a reflectance");
  }
  if (is_glass_kind(type)) refuse("two_sided", "glass is always two-sided (remove this key)");
  if (type == MaterialType::principled_thin) {
    refuse("two_sided", "a principled_thin material is two-sided by nature (remove this key)");
  }
  if (type == MaterialType::polarizer) {
    refuse("two_sided", "a polarizer is two-sided by nature (remove this key)");
    refuse("specular_transmittance", "a polarizer calls it transmittance");
  }
  if (type == MaterialType::hair) refuse("two_sided", "hair is two-sided by nature (remove this key)");
  if (type != MaterialType::principled_thin) {
    refuse("diff_trans", "only principled_thin materials have a diff_trans");
  }
  if (!is_rough(type)) refuse("alpha", "only rough kinds have an alpha");
  if (!is_conductor(type)) refuse("eta", "only conductors have an eta");
}

glm::dvec3 rgb_at_least(const JsonValue& value, double min) {
  glm::dvec3 rgb = value.vec3();
  std::vector<JsonValue> channels = value.elements(3);
  for (int i = 0; i < 3; ++i) {
    if (rgb[i] < min) channels[i].fail("must be >= " + format_number(min) + " (got " +
                                       format_number(rgb[i]) + ")");
  }
  return rgb;
}

MicrofacetDistribution parse_distribution(const JsonValue& value) {
  const std::string& name = value.string();
  if (name == "beckmann") return MicrofacetDistribution::beckmann;
  if (name == "ggx") return MicrofacetDistribution::ggx;
  value.fail("must be \"beckmann\" or \"ggx\" (got \"" + printable(name) + "\")");
}

void parse_roughness(const JsonValue& value, const TextureNames& textures, Material& m) {
  if (auto d = value.find("distribution")) m.distribution = parse_distribution(*d);
  m.sample_visible = value.boolean_or("sample_visible", true);
  std::optional<JsonValue> alpha = value.find("alpha");
  std::optional<JsonValue> alpha_u = value.find("alpha_u");
  std::optional<JsonValue> alpha_v = value.find("alpha_v");
  if (alpha && (alpha_u || alpha_v)) {
    (alpha_u ? alpha_u : alpha_v)->fail("give either alpha or alpha_u and alpha_v, not both");
  }
  if (alpha_u.has_value() != alpha_v.has_value()) {
    value.fail("alpha_u and alpha_v go together");
  }
  if (alpha) {
    m.alpha_u = m.alpha_v = parse_textured_float(*alpha, textures, 0, 1e300, true);
  } else if (alpha_u) {
    m.alpha_u = parse_textured_float(*alpha_u, textures, 0, 1e300, true);
    m.alpha_v = parse_textured_float(*alpha_v, textures, 0, 1e300, true);
  }
}

/// A finite number >= 0 (the principled kinds' sampling rates).
double parse_rate(const JsonValue& v) {
  const double rate = v.number();
  if (!(rate >= 0) || !std::isfinite(rate)) {
    v.fail("must be a finite number >= 0 (got " + format_number(rate) + ")");
  }
  return rate;
}

void parse_principled(const JsonValue& value, const TextureNames& textures, Material& m) {
  if (auto c = value.find("base_color")) m.reflectance = parse_textured_color(*c, textures, {0, 1});
  for (const PrincipledKey& k : kPrincipledWeights) {
    if (auto v = value.find(k.key)) {
      m.principled.*k.member = parse_textured_float(*v, textures, 0, 1, false);
    }
  }
  for (const auto& [key, member] : kPrincipledRates) {
    if (auto v = value.find(key)) m.principled.*member = parse_rate(*v);
  }
  if (m.principled.transmits() && m.two_sided) {
    value.find("two_sided")->fail(
        "a principled material with spec_trans transmits light and is two-sided by nature "
        "(remove this key, or set spec_trans to 0)");
  }
}

void parse_principled_thin(const JsonValue& value, const TextureNames& textures, Material& m) {
  if (auto c = value.find("base_color")) m.reflectance = parse_textured_color(*c, textures, {0, 1});
  for (const PrincipledKey& k : kThinWeights) {
    if (auto v = value.find(k.key)) {
      m.principled.*k.member = parse_textured_float(*v, textures, 0, 1, false);
    }
  }
  if (auto v = value.find("diff_trans")) {
    m.principled.diff_trans = parse_textured_float(*v, textures, 0, 2, false);
  }
  for (const auto& [key, member] : kThinRates) {
    if (auto v = value.find(key)) m.principled.*member = parse_rate(*v);
  }
}

void parse_type_keys(const JsonValue& value, const TextureNames& textures, Material& m);
void parse_common_keys(const JsonValue& value, const TextureNames& textures, Material& m);

/// A blend's weight (required, as in Mitsuba) and its two nested materials, which carry no
/// sidedness, mask or maps of their own.
void parse_blend(const JsonValue& value, const TextureNames& textures, Material& m) {
  std::optional<JsonValue> weight = value.find("weight");
  if (!weight) value.fail("a blend needs a \"weight\" (number in [0, 1] or texture)");
  m.blend_weight = parse_textured_float(*weight, textures, 0, 1, false);
  std::optional<JsonValue> materials = value.find("materials");
  if (!materials) value.fail("a blend needs \"materials\": [first, second]");
  std::vector<JsonValue> nested = materials->elements(2);
  for (size_t i = 0; i < nested.size(); ++i) {
    const JsonValue& n = nested[i];
    if (!n.json().is_object()) n.expect_object({}, "a material");
    for (const char* key : {"two_sided", "back", "opacity", "normal_map", "bump_map", "bump_scale"}) {
      if (std::optional<JsonValue> v = n.find(key)) {
        v->fail("a blend's nested material has no " + std::string(key) +
                " of its own (give it to the blend)");
      }
    }
    m.blend.push_back(parse_material(m.name + "[" + std::to_string(i) + "]", n, textures));
  }
  if (m.transmits() && m.two_sided) {
    value.find("two_sided")->fail(
        "a blend of a material that transmits light is two-sided by nature (remove this key)");
  }
}

void parse_type_keys(const JsonValue& value, const TextureNames& textures, Material& m) {
  MaterialType type = m.type;
  if (type == MaterialType::hair) return parse_hair_keys(value, textures, m);
  if (type == MaterialType::diffuse) {
    if (auto r = value.find("reflectance")) {
      m.reflectance = parse_textured_color(*r, textures, {0, 1});
    }
  }
  if (is_plastic(type)) {
    if (auto r = value.find("diffuse_reflectance")) {
      m.reflectance = parse_textured_color(*r, textures, {0, 1});
    }
    m.nonlinear = value.boolean_or("nonlinear", false);
  }
  if (auto s = value.find("specular_reflectance")) {
    m.specular_reflectance = parse_textured_color(*s, textures, {0, 1e300});
  }
  if (auto s = value.find("specular_transmittance")) {
    m.specular_transmittance = parse_textured_color(*s, textures, {0, 1e300});
  }
  if (type == MaterialType::polarizer) {
    if (auto t = value.find("transmittance")) {
      m.specular_transmittance = parse_textured_color(*t, textures, {0, 1});
    }
  }
  if (type == MaterialType::pplastic) {
    if (auto r = value.find("diffuse_reflectance")) {
      m.reflectance = parse_textured_color(*r, textures, {0, 1});
    }
  }
  if (auto ior = value.find("ior")) {
    if (type == MaterialType::principled_thin || type == MaterialType::pplastic) {
      // Mitsuba lets a texture give these two types' index.
      const TexturedFloat eta = parse_textured_float(*ior, textures, 0, 1e300, true);
      m.ior = eta.value;
      m.ior_texture = eta.texture;
    } else {
      m.ior = ior->number();
    }
    if (!(m.ior > 0)) ior->fail("must be > 0 (got " + format_number(m.ior) + ")");
  }
  if (is_conductor(type)) {
    if (auto eta = value.find("eta")) m.eta = rgb_at_least(*eta, 0);
    if (auto k = value.find("k")) m.k = rgb_at_least(*k, 0);
    m.perfect = value.boolean_or("perfect", false);
  }
  if (is_rough(type)) parse_roughness(value, textures, m);
  if (type == MaterialType::principled) parse_principled(value, textures, m);
  if (type == MaterialType::principled_thin) parse_principled_thin(value, textures, m);
  if (type == MaterialType::blend) parse_blend(value, textures, m);
}

void parse_common_keys(const JsonValue& value, const TextureNames& textures, Material& m) {
  m.two_sided = value.boolean_or("two_sided", false);
  if (auto o = value.find("opacity")) m.opacity = parse_textured_float(*o, textures, 0, 1, false);
  if (auto n = value.find("normal_map")) m.normal_map = texture_index(*n, textures);
  if (auto b = value.find("bump_map")) m.bump_map = texture_index(*b, textures);
  if (auto s = value.find("bump_scale")) m.bump_scale = s->number();
}

}  // namespace

bool is_glass_kind(MaterialType type) {
  return type == MaterialType::glass || type == MaterialType::rough_glass ||
         type == MaterialType::thin_glass;
}

Material parse_material(const std::string& name, const JsonValue& value,
                        const TextureNames& textures) {
  if (!value.json().is_object()) value.expect_object({}, "a material");
  Material material;
  material.name = name;
  material.type = parse_type(value);
  refuse_foreign_keys(value, material.type);
  const char* type_name = "diffuse";
  for (const auto& [text, kind] : kTypes) {
    if (kind == material.type) type_name = text;
  }
  value.expect_object(keys_of(material.type), std::string("a ") + type_name + " material");
  parse_common_keys(value, textures, material);
  parse_type_keys(value, textures, material);
  return material;
}

void parse_materials(const JsonValue& materials, MaterialTable& table,
                     const TextureNames& textures) {
  std::vector<std::pair<uint32_t, JsonValue>> backs;
  for (const auto& [name, value] : materials.members()) {
    if (name.empty()) value.fail("a material name must not be empty");
    uint32_t index = table.declare(parse_material(name, value, textures));
    if (value.json().is_object()) {
      if (auto back = value.find("back")) backs.emplace_back(index, *back);
    }
  }
  // "back" may name a material declared later.
  for (const auto& [index, back] : backs) {
    std::optional<uint32_t> other = table.find_declared(back.string());
    if (!other) back.fail("unknown material \"" + printable(back.string()) + "\"");
    if (*other == index) back.fail("must name another material");
    if (!table[*other].two_sided && !is_glass_kind(table[*other].type)) {
      back.fail("material \"" + printable(back.string()) +
                "\" must be two-sided (it is shaded with its own front)");
    }
    table.set_back(index, int32_t(*other));
  }
}

}  // namespace tessera
