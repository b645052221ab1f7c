// Mitsuba BSDFs as materials, named IORs, <ref> resolution and Mitsuba's default material.
#include <gtest/gtest.h>

#include "scene/mitsuba/mitsuba_ior.h"
#include "scene/mitsuba/mitsuba_test_support.h"

namespace tessera {
namespace {

using testing::line_of;
using testing::mitsuba_scene;
using testing::parse_xml;
using testing::xml_error;

/// The material of one rectangle holding `bsdf`.
Material material_of(const std::string& bsdf) {
  Scene s = parse_xml(mitsuba_scene("<shape type=\"rectangle\">" + bsdf + "</shape>"));
  return s.materials.at(s.shapes.at(0).material);
}

std::string bsdf_error(const std::string& bsdf) {
  return xml_error(mitsuba_scene("<shape type=\"rectangle\">" + bsdf + "</shape>"));
}

TEST(MitsubaBsdf, Diffuse) {
  Material m = material_of(R"(<bsdf type="diffuse"><rgb name="reflectance" value="0.1, 0.2, 0.3"/>
      </bsdf>)");
  EXPECT_EQ(m.type, MaterialType::diffuse);
  EXPECT_EQ(m.reflectance.value, glm::dvec3(0.1, 0.2, 0.3));
  EXPECT_FALSE(m.two_sided);  // one-sided, as in Mitsuba
  EXPECT_EQ(material_of(R"(<bsdf type="diffuse"><float name="reflectance" value="0.25"/></bsdf>)")
                .reflectance.value,
            glm::dvec3(0.25));
  EXPECT_EQ(material_of(R"(<bsdf type="diffuse"><rgb name="reflectance" value="0.75"/></bsdf>)")
                .reflectance.value,
            glm::dvec3(0.75));
  EXPECT_EQ(material_of(R"(<bsdf type="diffuse"/>)").reflectance.value, glm::dvec3(0.5));
}

TEST(MitsubaBsdf, DiffuseReflectanceMustConserveEnergy) {
  EXPECT_NE(bsdf_error(R"(<bsdf type="diffuse"><rgb name="reflectance" value="0.5, 1.2, 0"/>
      </bsdf>)")
                .find("<rgb name=\"reflectance\">: each channel must be in [0, 1] (got 1.2)"),
            std::string::npos);
}

TEST(MitsubaBsdf, TexturesAndSpectraAreRefused) {
  EXPECT_NE(bsdf_error(R"(<bsdf type="diffuse"><texture type="bitmap" name="reflectance">
      <string name="filename" value="wood.png"/></texture></bsdf>)")
                .find("<texture type=\"bitmap\" name=\"reflectance\">: textures are not "
                      "supported: give reflectance as <rgb> or <float>"),
            std::string::npos);
  EXPECT_NE(bsdf_error(R"(<bsdf type="diffuse"><spectrum name="reflectance" value="0.5"/></bsdf>)")
                .find("Tessera renders in RGB and reads no spectra: give reflectance as <rgb> or "
                      "<float>"),
            std::string::npos);
}

TEST(MitsubaBsdf, ConductorWithoutMaterialIsTheMirror) {
  EXPECT_EQ(
      material_of(R"(<bsdf type="conductor"><string name="material" value="none"/></bsdf>)").type,
      MaterialType::mirror);
  EXPECT_EQ(material_of(R"(<bsdf type="conductor"/>)").type, MaterialType::mirror);  // the default
  EXPECT_EQ(material_of(R"(<bsdf type="conductor"><rgb name="specular_reflectance" value="1"/>
      </bsdf>)")
                .type,
            MaterialType::mirror);
  EXPECT_NE(bsdf_error(R"(<bsdf type="conductor"><string name="material" value="Au"/></bsdf>)")
                .find("material \"Au\": Tessera's only conductor is the perfect mirror"),
            std::string::npos);
  EXPECT_NE(bsdf_error(R"(<bsdf type="conductor"><rgb name="eta" value="0.2"/></bsdf>)")
                .find("<rgb name=\"eta\">: is not supported in <bsdf type=\"conductor\"> "
                      "(Tessera reads: material, specular_reflectance)"),
            std::string::npos);
  EXPECT_NE(bsdf_error(R"(<bsdf type="conductor"><rgb name="specular_reflectance" value="0.9"/>
      </bsdf>)")
                .find("specular_reflectance must be 1: Tessera's mirror has no tint"),
            std::string::npos);
}

TEST(MitsubaBsdf, DielectricIorIsInteriorOverExterior) {
  Material m = material_of(R"(<bsdf type="dielectric"><float name="int_ior" value="1.5"/>
      <float name="ext_ior" value="1.25"/></bsdf>)");
  EXPECT_EQ(m.type, MaterialType::glass);
  EXPECT_EQ(m.ior, 1.5 / 1.25);
  EXPECT_EQ(material_of(R"(<bsdf type="dielectric"/>)").ior, 1.5046 / 1.000277);  // bk7 / air
  EXPECT_EQ(material_of(R"(<bsdf type="dielectric"><string name="int_ior" value="water"/>
      <string name="ext_ior" value="vacuum"/></bsdf>)")
                .ior,
            1.333);
  EXPECT_EQ(material_of(R"(<bsdf type="dielectric"><string name="int_ior" value="Diamond"/>
      <string name="ext_ior" value="water"/></bsdf>)")
                .ior,
            2.419 / 1.333);
}

TEST(MitsubaBsdf, BadIorsAreRefused) {
  EXPECT_NE(bsdf_error(R"(<bsdf type="dielectric"><string name="int_ior" value="unobtainium"/>
      </bsdf>)")
                .find("unknown IOR name \"unobtainium\" (Mitsuba's names: vacuum, helium"),
            std::string::npos);
  EXPECT_NE(bsdf_error(R"(<bsdf type="dielectric"><float name="int_ior" value="0"/></bsdf>)")
                .find("<float name=\"int_ior\">: must be > 0 (got 0)"),
            std::string::npos);
  EXPECT_NE(bsdf_error(R"(<bsdf type="dielectric"><rgb name="specular_transmittance" value="0.5"/>
      </bsdf>)")
                .find("specular_transmittance must be 1: Tessera's glass has no tint"),
            std::string::npos);
}

TEST(MitsubaIor, MitsubasTable) {
  EXPECT_EQ(mitsuba_named_ior("vacuum"), 1.0);
  EXPECT_EQ(mitsuba_named_ior("air"), 1.000277);
  EXPECT_EQ(mitsuba_named_ior("water"), 1.333);
  EXPECT_EQ(mitsuba_named_ior("bk7"), 1.5046);
  EXPECT_EQ(mitsuba_named_ior("BK7"), 1.5046);
  EXPECT_EQ(mitsuba_named_ior("acrylic glass"), 1.49);
  EXPECT_EQ(mitsuba_named_ior("fused quartz"), 1.458);
  EXPECT_EQ(mitsuba_named_ior("diamond"), 2.419);
  EXPECT_EQ(mitsuba_named_ior("water ice"), 1.31);
  EXPECT_EQ(mitsuba_named_ior("glass"), std::nullopt);  // not in Mitsuba's table either
  EXPECT_EQ(mitsuba_named_ior(""), std::nullopt);
  EXPECT_NE(mitsuba_ior_names().find("bk7, sodium chloride"), std::string::npos);
}

TEST(MitsubaBsdf, TwosidedWrapsDiffuseAndConductor) {
  Material d = material_of(R"(<bsdf type="twosided"><bsdf type="diffuse">
      <rgb name="reflectance" value="0.2"/></bsdf></bsdf>)");
  EXPECT_EQ(d.type, MaterialType::diffuse);
  EXPECT_TRUE(d.two_sided);
  EXPECT_EQ(d.reflectance.value, glm::dvec3(0.2));
  Material c = material_of(R"(<bsdf type="twosided"><bsdf type="conductor"/></bsdf>)");
  EXPECT_EQ(c.type, MaterialType::mirror);
  EXPECT_TRUE(c.two_sided);
}

TEST(MitsubaBsdf, TwosidedLimits) {
  EXPECT_NE(bsdf_error(R"(<bsdf type="twosided"><bsdf type="dielectric"/></bsdf>)")
                .find("twosided may wrap only diffuse or conductor"),
            std::string::npos);
  EXPECT_NE(bsdf_error(R"(<bsdf type="twosided"><bsdf type="diffuse"/><bsdf type="conductor"/>
      </bsdf>)")
                .find("has two BSDFs (different front and back)"),
            std::string::npos);
  EXPECT_NE(bsdf_error(R"(<bsdf type="twosided"/>)").find("needs one nested BSDF"),
            std::string::npos);
}

TEST(MitsubaBsdf, UnsupportedBsdfsNameTheirLine) {
  std::string body =
      "<bsdf type=\"diffuse\" id=\"ok\"/>\n<bsdf type=\"roughplastic\" id=\"p\">\n"
      "  <float name=\"alpha\" value=\"0.1\"/>\n</bsdf>";
  std::string xml = mitsuba_scene(body);
  // Refused even when no shape uses it.
  EXPECT_EQ(xml_error(xml),
            "test.xml: line " + std::to_string(line_of(xml, "roughplastic")) +
                ": <bsdf type=\"roughplastic\" id=\"p\">: unsupported BSDF (Tessera "
                "supports diffuse, conductor with material=\"none\" (a mirror), "
                "dielectric and twosided)");
  EXPECT_NE(bsdf_error(R"(<bsdf type="principled"/>)").find("unsupported BSDF"), std::string::npos);
}

TEST(MitsubaRef, ABsdfNamedTwiceIsOneMaterial) {
  std::string xml = mitsuba_scene(R"(
    <shape type="rectangle"><ref id="white"/></shape>
    <bsdf type="diffuse" id="white"><rgb name="reflectance" value="0.8"/></bsdf>
    <shape type="cube"><ref name="bsdf" id="white"/></shape>
    <shape type="disk"><bsdf type="diffuse"/></shape>)");
  Scene s = parse_xml(xml);
  ASSERT_EQ(s.shapes.size(), 3u);
  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_EQ(s.shapes[0].material, 0u);  // a <ref> may precede its target, as in Mitsuba 3
  EXPECT_EQ(s.shapes[1].material, 0u);
  EXPECT_EQ(s.materials[0].name, "white");
  EXPECT_EQ(s.materials[0].reflectance.value, glm::dvec3(0.8));
  EXPECT_EQ(s.materials[1].name, "diffuse (test.xml line " +
                                     std::to_string(line_of(xml, "<shape type=\"disk\">")) + ")");
}

TEST(MitsubaRef, BadReferences) {
  std::string xml = mitsuba_scene("<shape type=\"cube\">\n<ref id=\"nothing\"/>\n</shape>");
  EXPECT_EQ(xml_error(xml), "test.xml: line " + std::to_string(line_of(xml, "<ref")) +
                                ": <ref id=\"nothing\">: no object has id \"nothing\"");
  std::string twice = mitsuba_scene(
      "<bsdf type=\"diffuse\" id=\"a\"/>\n<shape type=\"cube\" "
      "id=\"a\"/>");
  EXPECT_EQ(xml_error(twice), "test.xml: line " + std::to_string(line_of(twice, "<shape")) +
                                  ": <shape type=\"cube\" id=\"a\">: duplicate id \"a\" (first at "
                                  "test.xml line " +
                                  std::to_string(line_of(twice, "<bsdf")) + ")");
  // A <ref> to an object that is not a BSDF is not taken as one.
  EXPECT_NE(xml_error(mitsuba_scene(R"(<shape type="cube" id="c"/>
      <shape type="rectangle"><ref id="c"/></shape>)"))
                .find("<ref id=\"c\">: (it names <shape type=\"cube\" id=\"c\">) is not supported "
                      "in <shape type=\"rectangle\">"),
            std::string::npos);
  EXPECT_NE(xml_error(mitsuba_scene(R"(<shape type="cube"><bsdf type="diffuse"/>
      <bsdf type="diffuse"/></shape>)"))
                .find("a shape has at most one BSDF"),
            std::string::npos);
}

TEST(MitsubaBsdf, ShapesWithoutBsdfGetMitsubasDefault) {
  Scene s = parse_xml(mitsuba_scene(R"(
    <shape type="rectangle"/>
    <shape type="cube"><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>)"));
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.shapes[0].material, 0u);
  EXPECT_EQ(s.shapes[1].material, 0u);  // an emitter without a BSDF reflects too, as in Mitsuba
  EXPECT_EQ(s.materials[0].type, MaterialType::diffuse);
  EXPECT_EQ(s.materials[0].reflectance.value, glm::dvec3(0.5));
  EXPECT_FALSE(s.materials[0].two_sided);
}

TEST(MitsubaBsdf, MaterialNamesAreUnique) {
  Scene s = parse_xml(mitsuba_scene(R"xml(
    <shape type="rectangle"><bsdf type="diffuse" id="(Mitsuba default diffuse)"/></shape>
    <shape type="cube"/>)xml"));
  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_EQ(s.materials[0].name, "(Mitsuba default diffuse)");
  EXPECT_EQ(s.materials[1].name, "(Mitsuba default diffuse) #2");
}

}  // namespace
}  // namespace tessera
