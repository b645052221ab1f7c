#include "scene/native/hair_material.h"

#include <cmath>

#include "scene/scene_error.h"

namespace tessera {
namespace {

/// A finite number in [min, max].
double number_in(const JsonValue& v, double min, double max) {
  const double x = v.number();
  if (!(x >= min && x <= max)) {
    v.fail("must be in [" + format_number(min) + ", " + format_number(max) + "] (got " +
           format_number(x) + ")");
  }
  return x;
}

/// A pigment concentration: a finite number >= 0.
double concentration(const JsonValue& v) {
  const double x = v.number();
  if (!(x >= 0)) v.fail("must be >= 0 (got " + format_number(x) + ")");
  return x;
}

}  // namespace

std::vector<std::string_view> hair_material_keys() {
  return {"type",       "eumelanin", "pheomelanin", "sigma_a",
          "ior",        "longitudinal_roughness",     "azimuthal_roughness",
          "scale_tilt", "opacity",   "normal_map",  "bump_map",
          "bump_scale", "back"};
}

void parse_hair_keys(const JsonValue& value, const TextureNames& textures, Material& m) {
  std::optional<JsonValue> eumelanin = value.find("eumelanin");
  std::optional<JsonValue> pheomelanin = value.find("pheomelanin");
  if (std::optional<JsonValue> sigma_a = value.find("sigma_a")) {
    if (eumelanin || pheomelanin) {
      sigma_a->fail("give either sigma_a or eumelanin and pheomelanin, not both (as Mitsuba "
                    "requires)");
    }
    m.hair.sigma_a = parse_textured_color(*sigma_a, textures, {0, 1e300});
  } else {
    const double eu = eumelanin ? concentration(*eumelanin) : 1.3;
    const double pheo = pheomelanin ? concentration(*pheomelanin) : 0.2;
    m.hair.sigma_a = {melanin_sigma_a(eu, pheo), -1};
  }
  m.ior = 1.55 / 1.000277;  // Mitsuba's amber in air
  if (std::optional<JsonValue> ior = value.find("ior")) {
    m.ior = ior->number();
    if (!(m.ior > 0) || m.ior == 1) {
      ior->fail("must be > 0 and differ from 1 (got " + format_number(m.ior) + ")");
    }
  }
  if (auto v = value.find("longitudinal_roughness")) {
    m.hair.longitudinal_roughness = number_in(*v, 0, 1);
  }
  if (auto v = value.find("azimuthal_roughness")) m.hair.azimuthal_roughness = number_in(*v, 0, 1);
  if (auto v = value.find("scale_tilt")) m.hair.scale_tilt_deg = v->number();
}

}  // namespace tessera
