#include "scene/native/material_parser.h"

namespace tessera {
namespace {

MaterialType parse_type(const JsonValue& value) {
  std::optional<JsonValue> type = value.find("type");
  if (!type) return MaterialType::diffuse;
  const std::string& name = type->string();
  if (name == "diffuse") return MaterialType::diffuse;
  if (name == "mirror") return MaterialType::mirror;
  if (name == "glass") return MaterialType::glass;
  type->fail("unknown material type \"" + printable(name) +
             "\" (expected diffuse, mirror or glass)");
}

/// Keys that belong to another type get a message saying whose they are.
void refuse_foreign_keys(const JsonValue& value, MaterialType type) {
  if (type != MaterialType::glass) {
    if (std::optional<JsonValue> ior = value.find("ior")) ior->fail("only glass has an ior");
  }
  if (type != MaterialType::diffuse) {
    if (std::optional<JsonValue> r = value.find("reflectance")) {
      r->fail("only diffuse materials have a reflectance");
    }
  }
  if (type == MaterialType::glass) {
    if (std::optional<JsonValue> t = value.find("two_sided")) {
      t->fail("glass is always two-sided (remove this key)");
    }
  }
}

glm::dvec3 parse_reflectance(const JsonValue& value) {
  glm::dvec3 rgb = value.vec3();
  std::vector<JsonValue> channels = value.elements(3);
  for (int i = 0; i < 3; ++i) {
    if (rgb[i] < 0 || rgb[i] > 1) {
      channels[i].fail("must be in [0, 1] (got " + format_number(rgb[i]) + ")");
    }
  }
  return rgb;
}

}  // namespace

Material parse_material(const std::string& name, const JsonValue& value) {
  if (!value.json().is_object()) value.expect_object({}, "a material");
  Material material;
  material.name = name;
  material.type = parse_type(value);
  refuse_foreign_keys(value, material.type);
  switch (material.type) {
    case MaterialType::diffuse:
      value.expect_object({"type", "reflectance", "two_sided"}, "a diffuse material");
      if (std::optional<JsonValue> r = value.find("reflectance")) {
        material.reflectance.value = parse_reflectance(*r);
      }
      material.two_sided = value.boolean_or("two_sided", false);
      break;
    case MaterialType::mirror:
      value.expect_object({"type", "two_sided"}, "a mirror material");
      material.two_sided = value.boolean_or("two_sided", false);
      break;
    case MaterialType::glass:
      value.expect_object({"type", "ior"}, "a glass material");
      if (std::optional<JsonValue> ior = value.find("ior")) {
        material.ior = ior->number();
        if (!(material.ior > 0)) ior->fail("must be > 0 (got " + format_number(material.ior) + ")");
      }
      break;
    // Only Mitsuba scenes have these (parse_type never returns them for native JSON).
    case MaterialType::conductor:
    case MaterialType::rough_conductor:
    case MaterialType::rough_glass:
    case MaterialType::thin_glass:
    case MaterialType::plastic:
    case MaterialType::rough_plastic:
      break;
  }
  return material;
}

void parse_materials(const JsonValue& materials, MaterialTable& table) {
  for (const auto& [name, value] : materials.members()) {
    if (name.empty()) value.fail("a material name must not be empty");
    table.declare(parse_material(name, value));
  }
}

}  // namespace tessera
