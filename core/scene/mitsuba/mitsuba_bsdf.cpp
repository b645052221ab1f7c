#include "scene/mitsuba/mitsuba_bsdf.h"

#include <cmath>

#include "scene/native/json_value.h"
#include "scene/mitsuba/mitsuba_ior.h"
#include "scene/mitsuba/mitsuba_plugin.h"

namespace tessera {
namespace {

constexpr const char* kSupported =
    "Tessera supports diffuse, conductor with material=\"none\" (a mirror), dielectric and "
    "twosided";

/// Accepts `name` only at Mitsuba's default of 1, which is what Tessera renders.
void expect_unit(MitsubaPlugin& plugin, const std::string& name) {
  std::optional<glm::dvec3> value = plugin.take_color(name);
  if (value && *value != glm::dvec3(1)) {
    fail_at(*plugin.property(name), name + " must be 1: Tessera's " +
                                        (plugin.type() == "conductor" ? "mirror" : "glass") +
                                        " has no tint");
  }
}

Material read_diffuse(MitsubaPlugin& plugin) {
  Material m;
  m.type = MaterialType::diffuse;
  m.reflectance.value = plugin.take_color("reflectance").value_or(glm::dvec3(0.5));
  for (int i = 0; i < 3; ++i) {
    if (!(m.reflectance.value[i] >= 0 && m.reflectance.value[i] <= 1)) {
      fail_at(*plugin.property("reflectance"),
              "each channel must be in [0, 1] (got " + format_number(m.reflectance.value[i]) + ")");
    }
  }
  return m;
}

Material read_conductor(MitsubaPlugin& plugin) {
  std::optional<std::string> material = plugin.take_string("material");
  if (material && *material != "none") {
    fail_at(*plugin.property("material"),
            "material \"" + printable(*material) +
                "\": Tessera's only conductor is the perfect mirror (material=\"none\")");
  }
  expect_unit(plugin, "specular_reflectance");
  Material m;
  m.type = MaterialType::mirror;
  return m;
}

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

Material read_dielectric(MitsubaPlugin& plugin) {
  Material m;
  m.type = MaterialType::glass;
  double interior = read_ior(plugin, "int_ior", "bk7");
  double exterior = read_ior(plugin, "ext_ior", "air");
  m.ior = interior / exterior;
  if (!std::isfinite(m.ior) || !(m.ior > 0)) {
    fail_at(plugin.element(), "int_ior / ext_ior is not a usable index of refraction");
  }
  expect_unit(plugin, "specular_reflectance");
  expect_unit(plugin, "specular_transmittance");
  return m;
}

Material read_twosided(MitsubaPlugin& plugin, const MitsubaIds& ids) {
  std::vector<MitsubaObject> nested = plugin.take_objects("bsdf");
  if (nested.size() != 1) {
    fail_at(plugin.element(), nested.empty()
                                  ? "needs one nested BSDF"
                                  : "has two BSDFs (different front and back): Tessera's two-sided "
                                    "materials are alike on both sides");
  }
  const MitsubaElement& inner = *nested.front().element;
  const std::string* type = inner.attribute("type");
  if (type && (*type == "twosided" || *type == "dielectric")) {
    fail_at(*nested.front().written,
            "twosided may wrap only diffuse or conductor (a dielectric is two-sided already)");
  }
  Material m = read_mitsuba_bsdf(inner, ids);
  m.two_sided = true;
  return m;
}

}  // namespace

Material read_mitsuba_bsdf(const MitsubaElement& bsdf, const MitsubaIds& ids) {
  MitsubaPlugin plugin(bsdf, ids);
  Material m;
  if (plugin.type() == "diffuse") {
    m = read_diffuse(plugin);
  } else if (plugin.type() == "conductor") {
    m = read_conductor(plugin);
  } else if (plugin.type() == "dielectric") {
    m = read_dielectric(plugin);
  } else if (plugin.type() == "twosided") {
    m = read_twosided(plugin, ids);
  } else {
    fail_at(bsdf, std::string("unsupported BSDF (") + kSupported + ")");
  }
  plugin.finish();
  return m;
}

uint32_t MitsubaMaterials::add(Material material, std::string name) {
  std::string unique = name;
  for (int k = 2; names_.count(unique); ++k) unique = name + " #" + std::to_string(k);
  names_.insert(unique);
  material.name = unique;
  materials_.push_back(std::move(material));
  return uint32_t(materials_.size() - 1);
}

uint32_t MitsubaMaterials::of(const MitsubaElement& bsdf) {
  auto it = index_of_.find(&bsdf);
  if (it != index_of_.end()) return it->second;
  Material material = read_mitsuba_bsdf(bsdf, ids_);
  std::string name;
  const std::string* id = bsdf.attribute("id");
  if (id && !id->empty()) {
    name = *id;
  } else {
    const std::string* type = bsdf.attribute("type");
    name = (type ? *type : std::string("bsdf")) + " (" + bsdf.file + " line " +
           std::to_string(bsdf.line) + ")";
  }
  uint32_t index = add(std::move(material), name);
  index_of_[&bsdf] = index;
  return index;
}

uint32_t MitsubaMaterials::default_material() {
  if (!default_) {
    Material diffuse;
    diffuse.type = MaterialType::diffuse;
    diffuse.reflectance.value = glm::dvec3(0.5);
    default_ = add(diffuse, "(Mitsuba default diffuse)");
  }
  return *default_;
}

std::vector<Material> MitsubaMaterials::take() {
  std::vector<Material> result = std::move(materials_);
  materials_.clear();
  index_of_.clear();
  names_.clear();
  default_.reset();
  return result;
}

}  // namespace tessera
