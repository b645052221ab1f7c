// Mitsuba's emitters: area emitters on shapes (constant, spectral, textured) and the lights
// that are not shapes.
#include <gtest/gtest.h>

#include <cmath>

#include "image/image_output.h"
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
}

// Mitsuba adds a shape's emitter to the scene's emitters whatever its type (scene.cpp): a spot
// written inside a shape (as in langevin-mc-rendering's scene_directional.xml) lights the scene
// from its own to_world, the shape does not glow, and its default BSDF is black (shape.cpp).
TEST(MitsubaEmitter, LightInsideAShapeIsALightOfTheScene) {
  Scene s = parse_xml(mitsuba_scene(R"(<shape type="rectangle">
      <transform name="to_world"><translate value="0, 2, 0"/></transform>
      <emitter type="spot"><rgb name="intensity" value="17, 12, 4"/>
        <float name="cutoff_angle" value="30"/></emitter></shape>
      <shape type="sphere"><bsdf type="diffuse"/><emitter type="point">
        <point name="position" value="1, 2, 3"/></emitter></shape>
      <emitter type="directional"/>)"));
  ASSERT_EQ(s.lights.size(), 3u);  // document order, as Mitsuba lists its emitters
  EXPECT_EQ(s.lights[0].kind, LightKind::spot);
  EXPECT_EQ(s.lights[0].to_world, glm::dmat4(1));  // not the shape's to_world
  EXPECT_EQ(s.lights[0].value, glm::dvec3(17, 12, 4));
  EXPECT_EQ(s.lights[0].cutoff_angle_deg, 30);
  EXPECT_EQ(s.lights[1].kind, LightKind::point);
  EXPECT_EQ(s.lights[2].kind, LightKind::directional);
  ASSERT_EQ(s.shapes.size(), 2u);
  for (const Shape& shape : s.shapes) {
    EXPECT_FALSE(shape.is_emitter());
    EXPECT_EQ(shape.emission, glm::dvec3(0));
  }
  EXPECT_EQ(s.materials.at(s.shapes[0].material).reflectance.value, glm::dvec3(0));
  EXPECT_EQ(s.materials.at(s.shapes[1].material).reflectance.value, glm::dvec3(0.5));

  // Still refused: two emitters, an environment inside a shape, a top-level light named by
  // <ref> (Mitsuba would list it twice), a light inside a shapegroup's shape (Mitsuba refuses
  // instanced emitters).
  const std::string two = mitsuba_scene(R"(<shape type="rectangle"><emitter type="point"/>
      <emitter type="area"/></shape>)");
  EXPECT_NE(xml_error(two).find("line " + std::to_string(line_of(two, "<emitter type=\"area")) +
                                ": <emitter type=\"area\">: a shape has at most one emitter"),
            std::string::npos)
      << xml_error(two);
  for (const char* environment : {"constant", "envmap"}) {
    const std::string xml = mitsuba_scene(R"(<shape type="rectangle"><emitter type=")" +
                                          std::string(environment) + R"("/></shape>)");
    EXPECT_NE(xml_error(xml).find(std::string("a ") + environment +
                                  " emitter inside a shape: Mitsuba samples it as a light but "
                                  "escaping rays do not see it"),
              std::string::npos)
        << xml_error(xml);
  }
  EXPECT_NE(xml_error(mitsuba_scene(R"(<emitter type="spot" id="s"/>
      <shape type="rectangle"><ref id="s"/></shape>)"))
                .find("a spot emitter named by <ref> inside a shape"),
            std::string::npos);
  const std::string grouped = mitsuba_scene(R"(<shape type="shapegroup" id="g">
      <shape type="sphere"><emitter type="point"/></shape></shape>
      <shape type="instance"><ref id="g"/></shape>)");
  EXPECT_NE(xml_error(grouped).find("a shapegroup's shapes cannot emit light"), std::string::npos)
      << xml_error(grouped);
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
  // The fuzzer's find: a direction whose squared length overflows (or underflows) gave a NaN
  // frame. Any non-zero finite direction gives a unit frame.
  for (const char* d : {"1e308, -1, -1", "-1e-310, 0, 1e-311", "1e308, 1e308, -1e308"}) {
    Light far = light_of(std::string(R"(<emitter type="directional"><vector name="direction" value=")") +
                         d + R"("/></emitter>)");
    const glm::dvec3 z(far.to_world[2]);
    EXPECT_NEAR(glm::length(z), 1.0, 1e-12) << d;
    EXPECT_NEAR(glm::length(glm::dvec3(far.to_world[0])), 1.0, 1e-12) << d;
    EXPECT_NEAR(glm::dot(z, glm::dvec3(far.to_world[0])), 0.0, 1e-12) << d;
  }
  Light far = light_of(R"(<emitter type="directional"><vector name="direction" value="1e308, -1, -1"/></emitter>)");
  testing::expect_near(glm::dvec3(far.to_world[2]), glm::dvec3(1, 0, 0));
  EXPECT_NE(xml_error(mitsuba_scene(R"(<emitter type="directional"><vector name="direction" value="0, 0, 0"/></emitter>)"))
                .find("must not be 0"),
            std::string::npos);
  EXPECT_NE(xml_error(mitsuba_scene(R"(<emitter type="spot"><float name="cutoff_angle" value="10"/>
      <float name="beam_width" value="20"/></emitter>)"))
                .find("beam_width must be in (0, cutoff_angle]"),
            std::string::npos);
  EXPECT_NE(xml_error(mitsuba_scene(R"(<emitter type="point"><point name="position" value="0"/>
      <transform name="to_world"><translate x="1"/></transform></emitter>)"))
                .find("give position or to_world, not both"),
            std::string::npos);
}

TEST(MitsubaEmitter, SpotWithATextureProjectedOverItsCone) {
  const std::string xml = mitsuba_scene(R"(<texture type="checkerboard" id="checks"/>
      <emitter type="spot"><rgb name="intensity" value="2"/>
        <texture type="bitmap" name="texture"><string name="filename" value="slide.png"/>
        </texture></emitter>
      <emitter type="spot"><ref name="texture" id="checks"/></emitter>)");
  const Scene s = parse_xml(xml, {{"slide.png", "png bytes are read by the renderer"}});
  ASSERT_EQ(s.lights.size(), 2u);
  ASSERT_EQ(s.textures.size(), 2u);
  ASSERT_GE(s.lights[0].texture, 0);
  ASSERT_GE(s.lights[1].texture, 0);
  EXPECT_EQ(s.textures.at(size_t(s.lights[0].texture)).file, "slide.png");
  EXPECT_EQ(s.lights[0].value, glm::dvec3(2));  // the texture multiplies the intensity
  EXPECT_EQ(s.textures.at(size_t(s.lights[1].texture)).kind, TextureKind::checkerboard);
  EXPECT_NE(std::find(s.referenced_files.begin(), s.referenced_files.end(), "slide.png"),
            s.referenced_files.end());
  // A constant is no texture, for Mitsuba either.
  const std::string constant =
      mitsuba_scene(R"(<emitter type="spot"><rgb name="texture" value="0.5"/></emitter>)");
  EXPECT_NE(xml_error(constant).find(
                "line " + std::to_string(line_of(constant, "<rgb name=\"texture\"")) +
                ": <rgb name=\"texture\">: a spot's texture must be a <texture>"),
            std::string::npos)
      << xml_error(constant);
}

TEST(MitsubaEmitter, ProjectorFramesItsImageLikeMitsuba) {
  // Mitsuba's defaults: irradiance 1, scale 1, focal_length 50mm (a diagonal fov) on a 1 x 1
  // image: x fov = 2 atan(43.27 / (2 * 50) / sqrt(2)) = 33.40 degrees.
  const Light plain = light_of(R"(<emitter type="projector"/>)");
  EXPECT_EQ(plain.kind, LightKind::projector);
  EXPECT_EQ(plain.value, glm::dvec3(1));
  EXPECT_EQ(plain.texture, -1);
  EXPECT_EQ(plain.aspect, 1);
  EXPECT_NEAR(plain.fov_x_deg,
              2 * std::atan(std::sqrt(36.0 * 36 + 24 * 24) / 100 / std::sqrt(2.0)) * 180 / M_PI,
              1e-12);
  const Light constant = light_of(R"(<emitter type="projector"><rgb name="irradiance"
      value="0.5, 1, 2"/><float name="scale" value="3"/><float name="fov" value="45"/>
      <transform name="to_world"><lookat origin="1, 1, 1" target="1, 2, 1" up="0, 0, 1"/>
      </transform></emitter>)");
  EXPECT_EQ(constant.value, glm::dvec3(1.5, 3, 6));  // irradiance times scale
  EXPECT_EQ(constant.fov_x_deg, 45);
  testing::expect_near(glm::dvec3(constant.to_world[2]), glm::dvec3(0, 1, 0));  // along +z
  // A bitmap's aspect comes from its pixels: 4 x 2 here, so a y fov of 30 is an x fov of
  // 2 atan(2 tan 15).
  const std::string png = encode_image(RgbImage{4, 2, std::vector<float>(4 * 2 * 3, 0.5f)}, "png");
  const Light textured = light_of(R"(<emitter type="projector"><texture type="bitmap"
      name="irradiance"><string name="filename" value="slide.png"/></texture>
      <float name="scale" value="2"/><float name="fov" value="30"/>
      <string name="fov_axis" value="y"/></emitter>)",
                                  {{"slide.png", png}});
  EXPECT_EQ(textured.texture, 0);
  EXPECT_EQ(textured.value, glm::dvec3(2));
  EXPECT_EQ(textured.aspect, 2);
  EXPECT_NEAR(textured.fov_x_deg, 2 * std::atan(2 * std::tan(M_PI / 12)) * 180 / M_PI, 1e-12);
  // An image that does not decode is refused at the texture, naming the file.
  const std::string broken = mitsuba_scene(R"(<emitter type="projector"><texture type="bitmap"
      name="irradiance"><string name="filename" value="slide.png"/></texture></emitter>)");
  EXPECT_NE(xml_error(broken, {{"slide.png", "not a png"}})
                .find("<texture type=\"bitmap\" name=\"irradiance\">: slide.png: "),
            std::string::npos)
      << xml_error(broken, {{"slide.png", "not a png"}});
  EXPECT_NE(xml_error(mitsuba_scene(R"(<emitter type="projector"><float name="fov"
      value="180"/></emitter>)"))
                .find("the field of view must be in (0, 180) degrees"),
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
  // A .pfm map (a float image, as Mitsuba reads it; its bytes are checked at submit).
  Scene pfm = parse_xml(mitsuba_scene(R"(<emitter type="envmap">
      <string name="filename" value="sky.pfm"/></emitter>)"),
                        {{"sky.pfm", "texels"}});
  EXPECT_EQ(pfm.lights.at(0).file, "sky.pfm");
  EXPECT_EQ(pfm.referenced_files, std::vector<std::string>{"sky.pfm"});
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
  EXPECT_NE(xml_error(mitsuba_scene(R"(<emitter type="sunsky"/>)"))
                .find("unsupported emitter (Tessera has area, point, spot, directional, constant, "
                      "envmap and projector)"),
            std::string::npos);
}

}  // namespace
}  // namespace tessera
