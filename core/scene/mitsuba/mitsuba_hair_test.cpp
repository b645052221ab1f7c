// Mitsuba's hair BSDF as a hair material: its parameters, defaults and checks (src/bsdfs/hair.cpp
// of Mitsuba 3.9.1), and the native JSON form it converts to.
#include <gtest/gtest.h>

#include "scene/mitsuba/mitsuba_test_support.h"
#include "scene/native/scene_writer.h"
#include "scene/file_reader.h"
#include "scene/native/scene_parser.h"

namespace tessera {
namespace {

using testing::mitsuba_scene;
using testing::parse_xml;
using testing::xml_error;

/// The material of one rectangle holding `bsdf` (Mitsuba accepts hair on any shape, though it is
/// meant for curves).
Material hair_of(const std::string& bsdf) {
  Scene s = parse_xml(mitsuba_scene("<shape type=\"rectangle\">" + bsdf + "</shape>"));
  return s.materials.at(s.shapes.at(0).material);
}

std::string hair_error(const std::string& bsdf) {
  return xml_error(mitsuba_scene("<shape type=\"rectangle\">" + bsdf + "</shape>"));
}

TEST(MitsubaHair, DefaultsAreMitsubas) {
  const Material m = hair_of(R"(<bsdf type="hair"/>)");
  EXPECT_EQ(m.type, MaterialType::hair);
  EXPECT_TRUE(m.transmits());
  EXPECT_DOUBLE_EQ(m.ior, 1.55 / 1.000277);  // amber over air
  // 1.3 eumelanin + 0.2 pheomelanin.
  EXPECT_NEAR(m.hair.sigma_a.value.x, 0.5821, 1e-12);
  EXPECT_NEAR(m.hair.sigma_a.value.y, 0.9861, 1e-12);
  EXPECT_NEAR(m.hair.sigma_a.value.z, 1.991, 1e-12);
  EXPECT_TRUE(m.hair.sigma_a.is_constant());
  EXPECT_EQ(m.hair.longitudinal_roughness, 0.3);
  EXPECT_EQ(m.hair.azimuthal_roughness, 0.3);
  EXPECT_EQ(m.hair.scale_tilt_deg, 2);
}

TEST(MitsubaHair, ReadsPigmentsOrAbsorption) {
  const Material p = hair_of(R"(<bsdf type="hair"><float name="eumelanin" value="0.2"/>
      <float name="pheomelanin" value="0.4"/><float name="scale" value="7"/>
      <float name="longitudinal_roughness" value="0.1"/>
      <float name="azimuthal_roughness" value="1"/><float name="scale_tilt" value="-3"/>
      <float name="int_ior" value="1.6"/><string name="ext_ior" value="water"/></bsdf>)");
  // scale acts on sigma_a only (Mitsuba reads it but pigments ignore it).
  EXPECT_NEAR(p.hair.sigma_a.value.x, 0.2 * 0.419 + 0.4 * 0.187, 1e-12);
  EXPECT_NEAR(p.hair.sigma_a.value.z, 0.2 * 1.37 + 0.4 * 1.05, 1e-12);
  EXPECT_EQ(p.hair.longitudinal_roughness, 0.1);
  EXPECT_EQ(p.hair.azimuthal_roughness, 1);
  EXPECT_EQ(p.hair.scale_tilt_deg, -3);
  EXPECT_DOUBLE_EQ(p.ior, 1.6 / 1.333);

  const Material a = hair_of(R"(<bsdf type="hair"><rgb name="sigma_a" value="0.2, 0.25, 0.7"/>
      <float name="scale" value="200"/></bsdf>)");
  EXPECT_NEAR(a.hair.sigma_a.value.x, 40, 1e-9);
  EXPECT_NEAR(a.hair.sigma_a.value.y, 50, 1e-9);
  EXPECT_NEAR(a.hair.sigma_a.value.z, 140, 1e-9);

  // An unbounded texture: its values times scale.
  const Material t = hair_of(R"(<bsdf type="hair"><texture name="sigma_a" type="checkerboard">
      <rgb name="color0" value="2"/></texture><float name="scale" value="3"/></bsdf>)");
  EXPECT_GE(t.hair.sigma_a.texture, 0);
  EXPECT_EQ(t.hair.sigma_a.value, glm::dvec3(3));
}

TEST(MitsubaHair, RefusesWhatMitsubaRefuses) {
  auto refused = [](const std::string& bsdf, const std::string& what) {
    const std::string e = hair_error(bsdf);
    EXPECT_NE(e.find(what), std::string::npos) << bsdf << " -> " << e;
  };
  refused(R"(<bsdf type="hair"><float name="longitudinal_roughness" value="1.5"/></bsdf>)",
          "must be in [0, 1] (got 1.5)");
  refused(R"(<bsdf type="hair"><float name="azimuthal_roughness" value="-0.1"/></bsdf>)",
          "must be in [0, 1]");
  refused(R"(<bsdf type="hair"><float name="int_ior" value="1.2"/>
      <float name="ext_ior" value="1.2"/></bsdf>)",
          "int_ior and ext_ior must differ");
  refused(R"(<bsdf type="hair"><rgb name="sigma_a" value="1"/>
      <float name="eumelanin" value="0.3"/></bsdf>)",
          "give either sigma_a or eumelanin and pheomelanin, not both");
  refused(R"(<bsdf type="hair"><float name="eumelanin" value="-1"/></bsdf>)", "must be >= 0");
  // Mitsuba's hair reads no eta or use_pigmentation ("unreferenced property").
  refused(R"(<bsdf type="hair"><float name="eta" value="1.3"/></bsdf>)",
          R"(<float name="eta">: is not supported in)");
  refused(R"(<bsdf type="hair"><boolean name="use_pigmentation" value="false"/></bsdf>)",
          R"(<boolean name="use_pigmentation">: is not supported in)");
  // Mitsuba's twosided takes no BSDF with transmission (hair's lobes are Glossy, both ways).
  refused(R"(<bsdf type="twosided"><bsdf type="hair"/></bsdf>)",
          "twosided takes only BSDFs that do not transmit");
}

TEST(MitsubaHair, ConvertsToNativeJsonAndBack) {
  Scene s = parse_xml(mitsuba_scene(R"(<shape type="rectangle"><bsdf type="hair">
      <float name="eumelanin" value="0.7"/><float name="scale_tilt" value="4"/>
      <float name="longitudinal_roughness" value="0.25"/></bsdf></shape>)"));
  const std::string json = write_scene_json(s);
  const Scene again = parse_scene(json, FileReader());
  const Material& m = again.materials.at(again.shapes.at(0).material);
  const Material& original = s.materials.at(s.shapes.at(0).material);
  EXPECT_EQ(m.type, MaterialType::hair);
  EXPECT_EQ(m.hair.sigma_a.value, original.hair.sigma_a.value);
  EXPECT_EQ(m.ior, original.ior);
  EXPECT_EQ(m.hair.longitudinal_roughness, 0.25);
  EXPECT_EQ(m.hair.azimuthal_roughness, 0.3);
  EXPECT_EQ(m.hair.scale_tilt_deg, 4);
  EXPECT_EQ(write_scene_json(again), json);
}

}  // namespace
}  // namespace tessera
