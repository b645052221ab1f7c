// Mitsuba's emitters: area emitters on shapes (constant, spectral, textured) and the lights
// that are not shapes.
#include <gtest/gtest.h>

#include "scene/mitsuba/mitsuba_test_support.h"

namespace tessera {
namespace {

using testing::line_of;
using testing::mitsuba_scene;
using testing::parse_xml;
using testing::xml_error;

Light light_of(const std::string& emitter, std::map<std::string, std::string> files = {}) {
  Scene s = parse_xml(mitsuba_scene(emitter), std::move(files));
  EXPECT_EQ(s.lights.size(), 1u);
  return s.lights.at(0);
}

TEST(MitsubaEmitter, AreaEmitterDefaultsAndTextures) {
  Scene s = parse_xml(mitsuba_scene(R"(<shape type="rectangle"><emitter type="area"/></shape>
      <shape type="disk"><emitter type="area"><texture type="bitmap" name="radiance">
      <string name="filename" value="sign.png"/></texture></emitter></shape>)"),
                      {{"sign.png", "x"}});
  EXPECT_EQ(s.shapes.at(0).emission, glm::dvec3(1));  // Mitsuba's RGB variants: radiance 1
  EXPECT_EQ(s.shapes.at(0).emission_texture, -1);
  EXPECT_EQ(s.shapes.at(1).emission, glm::dvec3(1));
  EXPECT_EQ(s.shapes.at(1).emission_texture, 0);
  EXPECT_EQ(s.textures.at(0).file, "sign.png");
  EXPECT_NE(xml_error(mitsuba_scene(R"(<shape type="rectangle"><emitter type="area">
      <rgb name="radiance" value="1, -1, 1"/></emitter></shape>)"))
                .find("each channel must be >= 0 (got -1)"),
            std::string::npos);
  EXPECT_NE(xml_error(mitsuba_scene(R"(<shape type="rectangle"><emitter type="point"/></shape>)"))
                .find("a shape's emitter must be \"area\""),
            std::string::npos);
}

TEST(MitsubaEmitter, SpectralRadianceIsMitsubasRgb) {
  // Mitsuba 3.9.1 scalar_rgb, traverse(...)['radiance.value'] of an emitter with this spectrum:
  // core/scene/mitsuba/testdata/spectrum_reference.py.
  Scene s = parse_xml(mitsuba_scene(R"(<shape type="rectangle"><emitter type="area">
      <spectrum name="radiance" value="400:0.1, 500:0.5, 600:0.9, 700:0.3"/></emitter></shape>)"));
  testing::expect_near(s.shapes.at(0).emission,
                       glm::dvec3(0.9992340207099915, 0.6596997976303101, 0.22944438457489014),
                       2e-5);
  // A flat emission spectrum keeps its colour under sRGB's D65 white: slightly purple.
  Scene flat = parse_xml(mitsuba_scene(R"(<shape type="rectangle"><emitter type="area">
      <spectrum name="radiance" value="0.5"/></emitter></shape>)"));
  testing::expect_near(flat.shapes.at(0).emission,
                       glm::dvec3(0.6023969650268555, 0.4741455018520355, 0.4544580280780792),
                       2e-5);
}

TEST(MitsubaEmitter, PointSpotAndDirectional) {
  Light point = light_of(R"(<emitter type="point"><point name="position" value="1, 2, 3"/>
      <rgb name="intensity" value="5"/></emitter>)");
  EXPECT_EQ(point.kind, LightKind::point);
  EXPECT_EQ(point.to_world[3], glm::dvec4(1, 2, 3, 1));
  EXPECT_EQ(point.value, glm::dvec3(5));
  Light spot = light_of(R"(<emitter type="spot"><float name="cutoff_angle" value="40"/>
      <transform name="to_world"><lookat origin="0, 5, 0" target="0, 0, 0"/></transform>
      </emitter>)");
  EXPECT_EQ(spot.kind, LightKind::spot);
  EXPECT_EQ(spot.cutoff_angle_deg, 40);
  EXPECT_EQ(spot.beam_width_deg, 30);  // Mitsuba's default: 3/4 of the cutoff
  testing::expect_near(glm::dvec3(spot.to_world[2]), glm::dvec3(0, -1, 0));  // shines along +z
  EXPECT_EQ(spot.value, glm::dvec3(1));
  Light sun = light_of(R"(<emitter type="directional"><vector name="direction" value="0, 0, -2"/>
      <float name="irradiance" value="3"/></emitter>)");
  EXPECT_EQ(sun.kind, LightKind::directional);
  testing::expect_near(glm::dvec3(sun.to_world[2]), glm::dvec3(0, 0, -1));
  EXPECT_EQ(sun.value, glm::dvec3(3));
  EXPECT_NE(xml_error(mitsuba_scene(R"(<emitter type="spot"><float name="cutoff_angle" value="10"/>
      <float name="beam_width" value="20"/></emitter>)"))
                .find("beam_width must be in (0, cutoff_angle]"),
            std::string::npos);
  EXPECT_NE(xml_error(mitsuba_scene(R"(<emitter type="point"><point name="position" value="0"/>
      <transform name="to_world"><translate x="1"/></transform></emitter>)"))
                .find("give position or to_world, not both"),
            std::string::npos);
}

TEST(MitsubaEmitter, ConstantAndEnvironmentMaps) {
  Light sky = light_of(R"(<emitter type="constant"><rgb name="radiance" value="0.5, 0.6, 0.7"/>
      </emitter>)");
  EXPECT_EQ(sky.kind, LightKind::constant);
  EXPECT_EQ(sky.value, glm::dvec3(0.5, 0.6, 0.7));
  Scene s = parse_xml(mitsuba_scene(R"(<emitter type="envmap">
      <string name="filename" value="maps/sky.exr"/><float name="scale" value="2"/>
      <transform name="to_world"><rotate y="1" angle="90"/></transform>
      <boolean name="mis_compensation" value="true"/></emitter>)"),
                      {{"maps/sky.exr", "texels"}});
  const Light& env = s.lights.at(0);
  EXPECT_EQ(env.kind, LightKind::envmap);
  EXPECT_EQ(env.file, "maps/sky.exr");
  EXPECT_EQ(env.value, glm::dvec3(2));
  testing::expect_near(glm::dvec3(env.to_world[0]), glm::dvec3(0, 0, -1));
  EXPECT_EQ(s.referenced_files, std::vector<std::string>{"maps/sky.exr"});
  std::string missing = mitsuba_scene(
      "<emitter type=\"envmap\">\n<string name=\"filename\" value=\"sky.exr\"/>\n</emitter>");
  EXPECT_EQ(xml_error(missing), "test.xml: line " + std::to_string(line_of(missing, "<string")) +
                                    ": <string name=\"filename\">: sky.exr: no such file in the "
                                    "scene's folder");
  EXPECT_NE(xml_error(mitsuba_scene(R"(<emitter type="envmap"><string name="filename"
      value="sky.exr"/><transform name="to_world"><scale value="2"/></transform></emitter>)"),
                      {{"sky.exr", "x"}})
                .find("this emitter's to_world must be a rotation and a translation"),
            std::string::npos);
  EXPECT_NE(xml_error(mitsuba_scene(R"(<emitter type="projector"/>)"))
                .find("unsupported emitter (Tessera has area, point, spot, directional, constant "
                      "and envmap)"),
            std::string::npos);
}

}  // namespace
}  // namespace tessera
