// Mitsuba's `volume` texture over gridvolume and constvolume, as the importer reads it
// (docs/mitsuba.md, "Textures").
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "scene/volume_grid_file.h"
#include "scene/mitsuba/mitsuba_test_support.h"
#include "scene/volume_grid_test_bytes.h"

namespace tessera {
namespace {

using testing::line_of;
using testing::mitsuba_scene;
using testing::parse_xml;
using testing::volume_grid_bytes;
using testing::xml_error;

const std::string kGrid =
    volume_grid_bytes({2, 1, 1}, 3, {1, 0, 0, 0, 1, 0}, {-1, 0, 0}, {1, 2, 4});

/// A rectangle whose diffuse reflectance is the volume texture with `inside`.
std::string diffuse_with(const std::string& inside) {
  return mitsuba_scene(R"(<shape type="rectangle"><bsdf type="diffuse">
      <texture type="volume" name="reflectance">)" + inside + R"(</texture></bsdf></shape>)");
}

std::string grid_with(const std::string& inside) {
  return diffuse_with(R"(<volume type="gridvolume" name="volume">
        <string name="filename" value="textures/red.vol"/>)" + inside + "</volume>");
}

TEST(MitsubaVolumeTexture, TheLegoTutorialsGrid) {
  // mitsuba-tutorials' scenes/lego/scene.xml, as written there.
  const Scene s = parse_xml(grid_with(""), {{"textures/red.vol", kGrid}});
  ASSERT_EQ(s.textures.size(), 1u);
  const Texture& t = s.textures[0];
  EXPECT_EQ(t.kind, TextureKind::volume);
  EXPECT_EQ(t.file, "textures/red.vol");
  ASSERT_TRUE(t.grid);
  EXPECT_EQ(t.grid->channels, 3u);
  EXPECT_EQ(t.filter, TextureFilter::bilinear);
  EXPECT_EQ(t.wrap, TextureWrap::clamp);
  EXPECT_EQ(t.volume_to_world, glm::dmat4(1.0));
  EXPECT_EQ(s.materials[0].reflectance.texture, 0);
  EXPECT_EQ(s.materials[0].reflectance.value, glm::dvec3(1));
  EXPECT_EQ(s.referenced_files, std::vector<std::string>{"textures/red.vol"});
}

TEST(MitsubaVolumeTexture, GridParameters) {
  const Scene s = parse_xml(grid_with(R"(<string name="filter_type" value="nearest"/>
        <string name="wrap_mode" value="mirror"/><boolean name="raw" value="true"/>
        <boolean name="accel" value="false"/>
        <transform name="to_world"><scale value="2"/><translate x="1"/></transform>)"),
                            {{"textures/red.vol", kGrid}});
  const Texture& t = s.textures[0];
  EXPECT_EQ(t.filter, TextureFilter::nearest);
  EXPECT_EQ(t.wrap, TextureWrap::mirror);
  const glm::dmat4 to_world = glm::scale(glm::translate(glm::dmat4(1.0), {1, 0, 0}), glm::dvec3(2));
  EXPECT_EQ(t.volume_to_world, to_world);
  const Scene r = parse_xml(grid_with(R"(<string name="wrap_mode" value="repeat"/>)"),
                            {{"textures/red.vol", kGrid}});
  EXPECT_EQ(r.textures[0].wrap, TextureWrap::repeat);
}

TEST(MitsubaVolumeTexture, UseGridBboxPlacesTheFilesBoxFirst) {
  // Mitsuba 3.9.1: to_local = bbox_transform * to_world^-1, bbox_transform mapping the file's
  // box [(-1, 0, 0), (1, 2, 4)] onto [0, 1]^3.
  const Scene s = parse_xml(grid_with(R"(<boolean name="use_grid_bbox" value="true"/>
        <transform name="to_world"><translate z="5"/></transform>)"),
                            {{"textures/red.vol", kGrid}});
  const glm::dmat4& m = s.textures[0].volume_to_world;
  EXPECT_EQ(glm::dvec3(m * glm::dvec4(0, 0, 0, 1)), glm::dvec3(-1, 0, 5));
  EXPECT_EQ(glm::dvec3(m * glm::dvec4(1, 1, 1, 1)), glm::dvec3(1, 2, 9));
}

TEST(MitsubaVolumeTexture, Constants) {
  auto constant = [](const std::string& inside) {
    const Scene s = parse_xml(diffuse_with(inside));
    EXPECT_EQ(s.textures[0].kind, TextureKind::volume);
    EXPECT_FALSE(s.textures[0].grid);
    EXPECT_TRUE(s.referenced_files.empty());
    return std::make_pair(s.textures[0].value, s.textures[0].channels);
  };
  EXPECT_EQ(constant(R"(<volume type="constvolume" name="volume"/>)"),
            std::make_pair(glm::dvec3(1), 1));
  // Unbounded, as Mitsuba 3.9.1 reads them (its eval of this gives [0.5, 2, 1]).
  EXPECT_EQ(constant(R"(<volume type="constvolume" name="volume">
      <rgb name="value" value="0.5, 2, 1"/></volume>)"),
            std::make_pair(glm::dvec3(0.5, 2, 1), 3));
  EXPECT_EQ(constant(R"(<volume type="constvolume" name="volume">
      <float name="value" value="-3"/></volume>)"),
            std::make_pair(glm::dvec3(-3), 1));
}

TEST(MitsubaVolumeTexture, AVolumeIsRequired) {
  // Mitsuba 3.9.1 refuses a <float> or <rgb> for "volume", and crashes at the first lookup of
  // a volume texture without one (its documented default, 0.75, is not made).
  const std::string as_float = diffuse_with(R"(<float name="volume" value="0.25"/>)");
  EXPECT_EQ(xml_error(as_float),
            "test.xml: line " + std::to_string(line_of(as_float, "name=\"volume\"")) +
                ": <float name=\"volume\">: The property \"volume\" has the wrong type "
                "(expected object, got float) (Mitsuba's message; a constant is <volume "
                "type=\"constvolume\" name=\"volume\">)");
  EXPECT_NE(xml_error(diffuse_with(R"(<rgb name="volume" value="0.1, 0.2, 0.3"/>)"))
                .find("(expected object, got rgb)"),
            std::string::npos);
  EXPECT_NE(xml_error(diffuse_with("")).find("missing <volume name=\"volume\">"),
            std::string::npos);
}

TEST(MitsubaVolumeTexture, ARefNamesOneTexture) {
  const Scene s = parse_xml(mitsuba_scene(R"(
    <texture type="volume" id="vt"><volume type="gridvolume" name="volume">
      <string name="filename" value="textures/red.vol"/></volume></texture>
    <shape type="rectangle"><bsdf type="diffuse"><ref name="reflectance" id="vt"/></bsdf></shape>
    <shape type="sphere"><bsdf type="roughconductor"><ref name="alpha" id="vt"/></bsdf></shape>)"),
                            {{"textures/red.vol", kGrid}});
  ASSERT_EQ(s.textures.size(), 1u);
  EXPECT_EQ(s.materials[1].alpha_u.texture, 0);
}

TEST(MitsubaVolumeTexture, RefusalsWithMitsubasReasons) {
  const std::map<std::string, std::string> files = {{"textures/red.vol", kGrid}};
  auto error = [&](const std::string& xml) { return xml_error(xml, files); };
  const std::string filter = grid_with(R"(<string name="filter_type" value="bilinear"/>)");
  EXPECT_EQ(error(filter),
            "test.xml: line " + std::to_string(line_of(filter, "name=\"filter_type\"")) +
                ": <string name=\"filter_type\">: Invalid filter type \"bilinear\", must be one "
                "of: \"nearest\" or \"trilinear\" (Mitsuba's message)");
  EXPECT_NE(error(grid_with(R"(<string name="wrap_mode" value="border"/>)"))
                .find("Invalid wrap mode \"border\", must be one of: \"repeat\", \"mirror\", or "
                      "\"clamp\""),
            std::string::npos);
  EXPECT_NE(error(diffuse_with(R"(<volume type="gridvolume" name="volume"/>)"))
                .find("missing <string name=\"filename\">"),
            std::string::npos);
  EXPECT_NE(error(diffuse_with(R"(<volume type="grid" name="volume"/>)"))
                .find("unsupported volume (Tessera's volume texture reads gridvolume and "
                      "constvolume)"),
            std::string::npos);
  EXPECT_NE(error(grid_with(R"(<float name="density" value="1"/>)")).find("density"),
            std::string::npos);
  const std::string two_channels =
      xml_error(grid_with(""), {{"textures/red.vol", volume_grid_bytes({1, 1, 1}, 2, {1, 2})}});
  EXPECT_NE(two_channels.find(": <string name=\"filename\">: textures/red.vol: has 2 channels"),
            std::string::npos)
      << two_channels;
  EXPECT_NE(xml_error(grid_with("")).find("red.vol"), std::string::npos);  // not in the bundle
  const std::string bump = mitsuba_scene(R"(<shape type="rectangle"><bsdf type="bumpmap">
      <texture type="volume"><volume type="gridvolume" name="volume">
        <string name="filename" value="textures/red.vol"/></volume></texture>
      <bsdf type="diffuse"/></bsdf></shape>)");
  EXPECT_NE(error(bump).find("cannot be a bump map (Mitsuba's volume texture has no gradient, "
                             "eval_1_grad)"),
            std::string::npos)
      << error(bump);
  for (const char* plastic : {"plastic", "roughplastic", "pplastic"}) {
    for (const char* parameter : {"diffuse_reflectance", "specular_reflectance"}) {
      const std::string xml = mitsuba_scene(std::string(R"(<shape type="rectangle"><bsdf type=")") +
                                            plastic + R"("><texture type="volume" name=")" +
                                            parameter + R"("><volume type="constvolume"
          name="volume"/></texture></bsdf></shape>)");
      EXPECT_NE(error(xml).find(std::string("Mitsuba's ") + plastic +
                                " takes the mean of its reflectances when it loads"),
                std::string::npos)
          << error(xml);
    }
  }
  const std::string emitter = mitsuba_scene(R"(<shape type="rectangle"><emitter type="area">
      <texture type="volume" name="radiance"><volume type="constvolume" name="volume"/>
      </texture>
      </emitter></shape>)");
  EXPECT_NE(error(emitter).find("which Tessera does not read for emitters"), std::string::npos)
      << error(emitter);
  const std::string spot = mitsuba_scene(R"(<emitter type="spot">
      <texture type="volume" name="texture"><volume type="gridvolume" name="volume">
        <string name="filename" value="textures/red.vol"/></volume></texture></emitter>)");
  EXPECT_NE(error(spot).find("cannot be a light's texture (Tessera looks it up by direction or "
                             "(u, v), with no surface point)"),
            std::string::npos)
      << error(spot);
  const std::string normals = mitsuba_scene(R"(<shape type="rectangle"><bsdf type="normalmap">
      <texture type="volume" name="normalmap"><volume type="gridvolume" name="volume">
        <string name="filename" value="textures/red.vol"/></volume></texture>
      <bsdf type="diffuse"/></bsdf></shape>)");
  EXPECT_NE(error(normals).find("cannot be a normal map"), std::string::npos) << error(normals);
}

}  // namespace
}  // namespace tessera
