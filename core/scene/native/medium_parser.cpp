#include "scene/native/medium_parser.h"

#include <cmath>

#include "scene/scene_error.h"

namespace tessera {
namespace {

std::string rgb_text(const glm::dvec3& v) {
  return "[" + format_number(v.x) + ", " + format_number(v.y) + ", " + format_number(v.z) + "]";
}

/// A medium's colour: a constant, or a volume texture times a scale (heterogeneous media, and
/// every medium's albedo: `texture_allowed`).
TexturedColor parse_medium_color(const JsonValue& value, const Medium& m,
                                 const std::vector<Texture>& textures,
                                 const TextureNames& texture_names, ColorRange range,
                                 bool texture_allowed) {
  TexturedColor c = parse_textured_color(value, texture_names, range);
  if (c.is_constant()) return c;
  if (m.kind != MediumKind::heterogeneous && !texture_allowed) {
    value.fail("a homogeneous medium's sigma_t is a constant [r, g, b] (a volume texture needs "
               "\"type\": \"heterogeneous\")");
  }
  if (textures[size_t(c.texture)].kind != TextureKind::volume) {
    value.at("texture").fail("a medium reads volume textures only (\"type\": \"volume\")");
  }
  return c;
}

}  // namespace

std::string medium_problem(const Medium& m, const std::vector<Texture>* textures) {
  auto bad = [](double x) { return !std::isfinite(x); };
  for (int c = 0; c < 3; ++c) {
    if (bad(m.sigma_t.value[c]) || m.sigma_t.value[c] < 0) {
      return "sigma_t must be finite and >= 0 (got " + rgb_text(m.sigma_t.value) + ")";
    }
    if (bad(m.albedo.value[c]) || m.albedo.value[c] < 0 ||
        (m.albedo.is_constant() && m.albedo.value[c] > 1)) {
      return "albedo must be in [0, 1] (got " + rgb_text(m.albedo.value) + ")";
    }
  }
  if (bad(m.scale) || m.scale < 0) return "scale must be finite and >= 0 (got " + format_number(m.scale) + ")";
  if (m.phase == PhaseKind::hg && !(std::abs(m.g) < 1)) {
    return "the hg phase function's g must be in (-1, 1) (got " + format_number(m.g) + ")";
  }
  for (const TexturedColor* c : {&m.sigma_t, &m.albedo}) {
    if (c->is_constant()) continue;
    if (m.kind != MediumKind::heterogeneous && c == &m.sigma_t) {
      return "a homogeneous medium's sigma_t cannot be a texture";
    }
    if (!textures) continue;
    if (size_t(c->texture) >= textures->size() || (*textures)[size_t(c->texture)].kind != TextureKind::volume) {
      return "a medium reads volume textures only";
    }
  }
  return "";
}

MediumNames parse_media(const JsonValue& value, const std::vector<Texture>& textures,
                        const TextureNames& texture_names, std::vector<Medium>& media) {
  MediumNames names;
  for (const auto& [name, item] : value.members()) {
    if (name.empty()) item.fail("a medium name must not be empty");
    item.expect_object({"type", "sigma_t", "albedo", "scale", "phase", "sample_emitters"}, "a medium");
    Medium m;
    m.name = name;
    m.origin = item.path();
    if (std::optional<JsonValue> type = item.find("type")) {
      const std::string& t = type->string();
      if (t == "heterogeneous") {
        m.kind = MediumKind::heterogeneous;
      } else if (t != "homogeneous") {
        type->fail("unknown medium type \"" + printable(t) + "\" (expected homogeneous or heterogeneous)");
      }
    }
    if (std::optional<JsonValue> s = item.find("sigma_t")) {
      m.sigma_t = parse_medium_color(*s, m, textures, texture_names, {0, 1e300}, false);
    }
    if (std::optional<JsonValue> a = item.find("albedo")) {
      m.albedo = parse_medium_color(*a, m, textures, texture_names, {0, 1}, true);
    }
    if (std::optional<JsonValue> s = item.find("scale")) {
      m.scale = s->number();
      if (m.scale < 0) s->fail("must be >= 0 (got " + format_number(m.scale) + ")");
    }
    if (std::optional<JsonValue> phase = item.find("phase")) {
      phase->expect_object({"type", "g"}, "a phase function");
      const std::string& t = phase->at("type").string();
      if (t == "hg") {
        m.phase = PhaseKind::hg;
        m.g = phase->number_or("g", 0.8);
        if (!(std::abs(m.g) < 1)) {
          phase->at("g").fail("must be in (-1, 1) (got " + format_number(m.g) + ")");
        }
      } else if (t == "isotropic") {
        if (phase->has("g")) phase->at("g").fail("an isotropic phase function has no g");
      } else {
        phase->at("type").fail("unknown phase function \"" + printable(t) + "\" (expected isotropic or hg)");
      }
    }
    m.sample_emitters = item.boolean_or("sample_emitters", true);
    names[name] = int32_t(media.size());
    media.push_back(std::move(m));
  }
  return names;
}

int32_t medium_index(const JsonValue& value, const MediumNames& media) {
  const std::string& name = value.string();
  auto it = media.find(name);
  if (it == media.end()) value.fail("unknown medium \"" + printable(name) + "\"");
  return it->second;
}

}  // namespace tessera
