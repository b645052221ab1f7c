#include "scene/mitsuba/mitsuba_hair.h"

#include <string>

#include "scene/message_text.h"

namespace tessera {
namespace {

/// A <float> in [0, 1] (the roughnesses), `fallback` when absent.
double read_unit_float(MitsubaPlugin& plugin, const std::string& name, double fallback) {
  const double x = plugin.take_float(name).value_or(fallback);
  if (!(x >= 0 && x <= 1)) {
    fail_at(*plugin.property(name), "must be in [0, 1] (got " + format_number(x) + ")");
  }
  return x;
}

/// A concentration: a <float> >= 0.
double read_concentration(MitsubaPlugin& plugin, const std::string& name, double fallback) {
  const double x = plugin.take_float(name).value_or(fallback);
  if (!(x >= 0)) fail_at(*plugin.property(name), "must be >= 0 (got " + format_number(x) + ")");
  return x;
}

}  // namespace

Material read_hair(MitsubaPlugin& plugin, MitsubaTextures& textures, double eta) {
  Material m;
  m.type = MaterialType::hair;
  if (eta == 1) {
    fail_at(plugin.element(), "int_ior and ext_ior must differ (as Mitsuba requires)");
  }
  m.ior = eta;
  const bool pigments = plugin.has("eumelanin") || plugin.has("pheomelanin");
  if (plugin.has("sigma_a") && pigments) {
    fail_at(*plugin.property("sigma_a"),
            "give either sigma_a or eumelanin and pheomelanin, not both (as Mitsuba requires)");
  }
  const double eumelanin = read_concentration(plugin, "eumelanin", 1.3);
  const double pheomelanin = read_concentration(plugin, "pheomelanin", 0.2);
  const double scale = plugin.take_float("scale").value_or(1.0);
  if (plugin.has("sigma_a")) {
    if (!(scale >= 0)) {
      fail_at(*plugin.property("scale"), "must be >= 0 (got " + format_number(scale) + ")");
    }
    m.hair.sigma_a = read_textured_color(plugin, "sigma_a", glm::dvec3(0),
                                         MitsubaColorRole::unbounded, textures);
    m.hair.sigma_a.value *= scale;
  } else {
    m.hair.sigma_a = {melanin_sigma_a(eumelanin, pheomelanin), -1};
  }
  m.hair.longitudinal_roughness = read_unit_float(plugin, "longitudinal_roughness", 0.3);
  m.hair.azimuthal_roughness = read_unit_float(plugin, "azimuthal_roughness", 0.3);
  m.hair.scale_tilt_deg = plugin.take_float("scale_tilt").value_or(2.0);
  return m;
}

}  // namespace tessera
