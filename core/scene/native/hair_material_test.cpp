// The native "hair" material: Mitsuba's parameters, their defaults, and bad values refused.
#include <gtest/gtest.h>

#include "scene/native/scene_writer.h"
#include "scene/native/native_test_support.h"

namespace tessera {
namespace {

using testing::error_of;
using testing::parse;

std::string with_material(const std::string& m, const std::string& extra = "") {
  return R"({"tessera": 1, "materials": {"m": )" + m + "}" + extra + "}";
}

TEST(HairMaterial, DefaultsAreMitsubas) {
  const Scene s = parse(with_material(R"({"type": "hair"})"));
  const Material& m = s.materials.at(0);
  EXPECT_EQ(m.type, MaterialType::hair);
  EXPECT_TRUE(m.transmits());
  EXPECT_EQ(m.hair.sigma_a.value, melanin_sigma_a(1.3, 0.2));
  EXPECT_DOUBLE_EQ(m.ior, 1.55 / 1.000277);
  EXPECT_EQ(m.hair.longitudinal_roughness, 0.3);
  EXPECT_EQ(m.hair.azimuthal_roughness, 0.3);
  EXPECT_EQ(m.hair.scale_tilt_deg, 2);
}

TEST(HairMaterial, ReadsPigmentsOrAbsorption) {
  const Scene s = parse(with_material(
      R"({"type": "hair", "eumelanin": 0.5, "pheomelanin": 1, "ior": 1.4,
          "longitudinal_roughness": 0.1, "azimuthal_roughness": 0.9, "scale_tilt": -1},
          "n": {"type": "hair", "sigma_a": {"texture": "h", "scale": 20}, "opacity": 0.5})",
      R"(, "textures": {"h": {"type": "checkerboard"}})"));
  const Material& m = s.materials.at(0);
  EXPECT_EQ(m.hair.sigma_a.value, melanin_sigma_a(0.5, 1));
  EXPECT_EQ(m.ior, 1.4);
  EXPECT_EQ(m.hair.longitudinal_roughness, 0.1);
  EXPECT_EQ(m.hair.azimuthal_roughness, 0.9);
  EXPECT_EQ(m.hair.scale_tilt_deg, -1);
  const Material& n = s.materials.at(1);
  EXPECT_EQ(n.hair.sigma_a.texture, 0);
  EXPECT_EQ(n.hair.sigma_a.value, glm::dvec3(20));
  EXPECT_EQ(n.opacity.value, 0.5);
  // Written and read again: the same scene, the same text.
  const std::string json = write_scene_json(s);
  EXPECT_EQ(write_scene_json(parse(json)), json);
  EXPECT_EQ(parse(json).materials.at(1).hair.sigma_a.texture, 0);
}

TEST(HairMaterial, RefusesBadValues) {
  auto error = [](const std::string& m) { return error_of(with_material(m)); };
  EXPECT_EQ(error(R"({"type": "hair", "sigma_a": [1, 1, 1], "eumelanin": 1})"),
            "materials.m.sigma_a: give either sigma_a or eumelanin and pheomelanin, not both (as "
            "Mitsuba requires)");
  EXPECT_EQ(error(R"({"type": "hair", "sigma_a": [1, -1, 1]})").rfind("materials.m.sigma_a[1]", 0),
            0u);
  EXPECT_EQ(error(R"({"type": "hair", "eumelanin": -0.5})"),
            "materials.m.eumelanin: must be >= 0 (got -0.5)");
  EXPECT_EQ(error(R"({"type": "hair", "longitudinal_roughness": 1.5})"),
            "materials.m.longitudinal_roughness: must be in [0, 1] (got 1.5)");
  EXPECT_EQ(error(R"({"type": "hair", "ior": 1})"),
            "materials.m.ior: must be > 0 and differ from 1 (got 1)");
  EXPECT_EQ(error(R"({"type": "hair", "two_sided": true})"),
            "materials.m.two_sided: hair is two-sided by nature (remove this key)");
  EXPECT_EQ(error(R"({"type": "hair", "reflectance": [1, 1, 1]})"),
            "materials.m.reflectance: only diffuse materials have a reflectance");
  EXPECT_EQ(error(R"({"type": "diffuse", "scale_tilt": 2})").rfind("materials.m.scale_tilt", 0),
            0u);
}

}  // namespace
}  // namespace tessera
