// Mitsuba textures the importer reads besides bitmaps and checkerboards: rawconstant.
#include <gtest/gtest.h>

#include "scene/mitsuba/mitsuba_test_support.h"

namespace tessera {
namespace {

using testing::line_of;
using testing::mitsuba_scene;
using testing::parse_xml;
using testing::xml_error;

TEST(MitsubaTexture, RawConstantKeepsItsValueAsWritten) {
  // Mitsuba's tests/scenes/bsdf_spheres normal-map scene: the identity normal as a raw vector.
  Scene s = parse_xml(mitsuba_scene(R"(<shape type="sphere"><bsdf type="normalmap">
      <texture name="normalmap" type="rawconstant"><vector name="value" value="0.5, 0.5, 1.0"/>
      </texture>
      <bsdf type="roughconductor"><float name="alpha_u" value="0.25"/>
        <float name="alpha_v" value="0.05"/></bsdf></bsdf></shape>
    <shape type="rectangle"><bsdf type="diffuse">
      <texture name="reflectance" type="rawconstant"><float name="value" value="1.5"/></texture>
    </bsdf></shape>)"));
  ASSERT_EQ(s.textures.size(), 2u);
  EXPECT_EQ(s.textures[0].kind, TextureKind::rawconstant);
  EXPECT_EQ(s.textures[0].value, glm::dvec3(0.5, 0.5, 1.0));
  EXPECT_EQ(s.textures[0].channels, 3);
  EXPECT_EQ(s.materials[0].normal_map, 0);
  EXPECT_EQ(s.textures[1].value, glm::dvec3(1.5));  // no range check, as in Mitsuba
  EXPECT_EQ(s.textures[1].channels, 1);
  EXPECT_EQ(s.materials[1].reflectance.texture, 1);
}

TEST(MitsubaTexture, RawConstantRefusals) {
  const std::string scalar_vector = mitsuba_scene(R"(<shape type="rectangle">
    <bsdf type="roughconductor">
      <texture name="alpha" type="rawconstant"><vector name="value" value="0.1, 0.2, 0.3"/>
      </texture></bsdf></shape>)");
  EXPECT_EQ(xml_error(scalar_vector),
            "test.xml: line " + std::to_string(line_of(scalar_vector, "<texture name=\"alpha\"")) +
                ": <texture type=\"rawconstant\" name=\"alpha\">: a rawconstant <vector> has no "
                "scalar value (Mitsuba's eval_1 refuses it): give \"alpha\" a <float> value");
  auto error_with = [](const std::string& inside) {
    return xml_error(mitsuba_scene(R"(<shape type="rectangle"><bsdf type="diffuse">
      <texture name="reflectance" type="rawconstant">)" + inside + R"(</texture></bsdf></shape>)"));
  };
  EXPECT_NE(error_with("").find("name=\"reflectance\">: missing \"value\" (a <float> or a <vector>)"),
            std::string::npos)
      << error_with("");
  EXPECT_NE(error_with(R"(<rgb name="value" value="0.5"/>)")
                .find("<rgb name=\"value\">: rawconstant's value is a <float> or a <vector>"),
            std::string::npos);
  EXPECT_NE(error_with(R"(<float name="value" value="0.5"/><transform name="to_uv">
        <scale x="2"/></transform>)")
                .find("<transform name=\"to_uv\">: is not supported in <texture"),
            std::string::npos)
      << error_with(R"(<float name="value" value="0.5"/><transform name="to_uv">
        <scale x="2"/></transform>)");
  const std::string spot = mitsuba_scene(R"(<emitter type="spot">
      <texture name="texture" type="rawconstant"><float name="value" value="2"/></texture>
    </emitter>)");
  EXPECT_NE(xml_error(spot).find("name=\"texture\">: a spot's texture must vary over the cone"),
            std::string::npos)
      << xml_error(spot);
}

}  // namespace
}  // namespace tessera
