// The importer on whole scenes: sensors, objects used by reference, top-level elements and
// refusals (the reference Cornell box read from disk: loader/scene_files_test.cpp).
#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include "scene/mitsuba/mitsuba_test_support.h"
#include "scene/mitsuba/mitsuba_transform.h"
#include "scene/native/scene_parser.h"
#include "scene/native/scene_writer.h"

namespace tessera {
namespace {

using testing::line_of;
using testing::mitsuba_scene;
using testing::parse_xml;
using testing::xml_error;

TEST(MitsubaScene, TheSceneNeedsASensor) {
  EXPECT_EQ(xml_error("<scene version=\"3.0.0\">\n<shape type=\"cube\"/>\n</scene>"),
            "test.xml: line 1: <scene>: the scene has no <sensor> (Tessera needs a perspective, "
            "thinlens or orthographic sensor; Mitsuba 3 loads such a scene but cannot render it "
            "either: \"No sensor specified\")");
}

// Blender exports (mitsuba-blender, as in Sionna's scenes) carry one sensor per Blender camera.
// Mitsuba 3.9.1 keeps them in document order (whatever their ids) and renders the first by
// default; so does Tessera. Every sensor is read: an unsupported one is still refused.
TEST(MitsubaScene, SeveralSensorsRenderTheFirst) {
  Scene s = parse_xml(R"(<scene version="3.0.0">
    <sensor type="perspective" id="zcam"><float name="fov" value="30"/>
      <film type="hdrfilm"><integer name="width" value="40"/><integer name="height" value="30"/>
      </film></sensor>
    <sensor type="perspective" id="acam"><float name="fov" value="60"/></sensor>
    <sensor type="thinlens"><float name="fov" value="70"/>
      <float name="aperture_radius" value="0.1"/></sensor>
  </scene>)");
  EXPECT_DOUBLE_EQ(s.camera.fov_deg, 30);
  EXPECT_EQ(s.film.width, 40);
  EXPECT_EQ(s.film.height, 30);
  EXPECT_EQ(s.camera.aperture_radius, 0);
  std::string unsupported = R"(<scene version="3.0.0">
    <sensor type="perspective"><float name="fov" value="30"/></sensor>
    <sensor type="radiancemeter"/>
  </scene>)";
  EXPECT_NE(xml_error(unsupported).find("test.xml: line 3: <sensor type=\"radiancemeter\">"),
            std::string::npos)
      << xml_error(unsupported);
}

TEST(MitsubaScene, TopLevelObjectsUsedByRef) {
  Scene s = parse_xml(mitsuba_scene(R"(
    <texture type="checkerboard" id="checks"><rgb name="color0" value="0.1"/></texture>
    <emitter type="area" id="lamp"><rgb name="radiance" value="5"/></emitter>
    <bsdf type="diffuse" id="floor"><ref name="reflectance" id="checks"/></bsdf>
    <shape type="rectangle"><ref id="floor"/><ref id="lamp"/></shape>
    <shape type="disk"><ref id="floor"/></shape>)"));
  ASSERT_EQ(s.textures.size(), 1u);
  EXPECT_EQ(s.textures[0].name, "checks");
  EXPECT_EQ(s.textures[0].kind, TextureKind::checkerboard);
  EXPECT_EQ(s.textures[0].color0, glm::dvec3(0.1));
  EXPECT_EQ(s.textures[0].color1, glm::dvec3(0.2));  // Mitsuba's default
  EXPECT_EQ(s.materials.at(0).reflectance.texture, 0);
  EXPECT_EQ(s.shapes.at(0).emission, glm::dvec3(5));
  EXPECT_FALSE(s.shapes.at(1).is_emitter());
  // A sampler declared at the top and named by the sensor.
  Scene sampled = parse_xml(R"(<scene version="3.0.0">
    <sampler type="independent" id="spp"><integer name="sample_count" value="32"/></sampler>
    <sensor type="perspective"><float name="fov" value="40"/><ref id="spp"/></sensor>
  </scene>)");
  EXPECT_EQ(sampled.render.spp, 32);
  // A film (with its filter) declared at the top and named by the sensor, as the Mitsuba 3
  // versions of Bitterli's scenes and BlendSwap exports write it (Mitsuba 3.9.1 loads this).
  Scene filmed = parse_xml(R"(<scene version="3.0.0">
    <film type="hdrfilm" id="film"><integer name="width" value="86"/>
      <integer name="height" value="72"/><rfilter type="box"/></film>
    <sampler type="independent" id="sampler"><integer name="sample_count" value="8"/></sampler>
    <sensor type="perspective"><float name="fov" value="40"/><ref id="sampler"/><ref id="film"/>
    </sensor>
  </scene>)");
  EXPECT_EQ(filmed.film.width, 86);
  EXPECT_EQ(filmed.film.height, 72);
  EXPECT_EQ(filmed.film.filter.kind, FilterKind::box);
  EXPECT_EQ(filmed.render.spp, 8);
}

// The fuzzer's find: a checkerboard colour above 1 was imported, then refused by the native
// parser when read back. Both now take any colour >= 0; a negative one is refused at import.
TEST(MitsubaScene, CheckerboardColoursAboveOneImportAndReadBack) {
  Scene s = parse_xml(mitsuba_scene(R"(
    <bsdf type="diffuse" id="bright"><texture name="reflectance" type="checkerboard">
      <float name="color0" value="5.8"/><rgb name="color1" value="1.5, 0, 2"/></texture></bsdf>
    <shape type="sphere"><ref id="bright"/></shape>)"));
  ASSERT_EQ(s.textures.size(), 1u);
  EXPECT_EQ(s.textures[0].color0, glm::dvec3(5.8));
  EXPECT_EQ(s.textures[0].color1, glm::dvec3(1.5, 0, 2));
  std::string json = write_scene_json(s);
  EXPECT_EQ(write_scene_json(parse_scene(json, testing::memory_reader({}))), json);

  std::string xml = mitsuba_scene(R"(
    <texture type="checkerboard" id="checks"><rgb name="color1" value="0.5, -0.25, 0.5"/></texture>
    <bsdf type="diffuse" id="floor"><ref name="reflectance" id="checks"/></bsdf>
    <shape type="disk"><ref id="floor"/></shape>)");
  EXPECT_NE(xml_error(xml).find("color1 must be >= 0 in every channel (got -0.25)"),
            std::string::npos)
      << xml_error(xml);
}

TEST(MitsubaScene, TopLevelElementsTesseraDoesNotRead) {
  auto error = [](const std::string& body) {
    std::string xml = mitsuba_scene(body);
    std::string message = xml_error(xml);
    EXPECT_NE(message.find("test.xml: line " + std::to_string(line_of(xml, body))),
              std::string::npos)
        << message;
    return message;
  };
  EXPECT_NE(error(R"(<emitter type="area"/>)").find("an area emitter belongs inside a <shape>"),
            std::string::npos);
  EXPECT_NE(error(R"(<texture type="perlin" id="t"/>)").find("unsupported texture"),
            std::string::npos);
  EXPECT_NE(error(R"(<medium type="fog" id="fog"/>)").find("unsupported medium"),
            std::string::npos);
  EXPECT_NE(error(R"(<phase type="hg"/>)").find("belongs inside a <medium>"), std::string::npos);
  EXPECT_NE(error(R"(<film type="hdrfilm"/>)").find("belongs inside the <sensor>"),
            std::string::npos);
  EXPECT_NE(error(R"(<sampler type="independent"/>)").find("belongs inside the <sensor>"),
            std::string::npos);
  EXPECT_NE(error(R"(<float name="x" value="1"/>)").find("not supported at the top of a scene"),
            std::string::npos);
  EXPECT_NE(error(R"(<alias id="a" as="b"/>)").find("not supported by Tessera's importer"),
            std::string::npos);
  EXPECT_NE(xml_error(mitsuba_scene(R"(<shape type="rectangle"><emitter type="area">
      <spectrum name="radiance" filename="d65.spd"/></emitter></shape>)"))
                .find("<spectrum name=\"radiance\">: spectra from files are not supported"),
            std::string::npos);
}

TEST(MitsubaScene, NothingOutsideTheSubsetIsDropped) {
  // A parameter Tessera does not read is an error even where Mitsuba would ignore it.
  EXPECT_NE(xml_error(mitsuba_scene(R"(<shape type="rectangle"><float name="colour" value="1"/>
      </shape>)"))
                .find("<float name=\"colour\">: is not supported in <shape type=\"rectangle\">"),
            std::string::npos);
}

}  // namespace
}  // namespace tessera
