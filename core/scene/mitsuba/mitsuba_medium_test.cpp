// Mitsuba's <medium>, <phase> and the volumetric integrators, as the importer reads them.
#include <gtest/gtest.h>

#include "scene/mitsuba/mitsuba_test_support.h"
#include "scene/native/scene_writer.h"
#include "scene/native/native_test_support.h"
#include "scene/volume_grid_test_bytes.h"

namespace tessera {
namespace {

using testing::mitsuba_scene;
using testing::parse_xml;
using testing::xml_error;

const char* kVolpath = R"(<integrator type="volpath"><integer name="max_depth" value="-1"/></integrator>)";

TEST(MitsubaMedium, ReadsHomogeneousMediaWithMitsubasDefaults) {
  const Scene s = parse_xml(mitsuba_scene(std::string(kVolpath) + R"(
    <medium id="medium1" type="homogeneous">
      <float name="scale" value="2.5"/>
      <rgb name="sigma_t" value="1, 0.2, 1"/>
      <rgb name="albedo" value="0.99, 0.5, 0.5"/>
      <phase type="hg"><float name="g" value="-0.4"/></phase>
      <boolean name="sample_emitters" value="false"/>
    </medium>
    <shape type="sphere"><bsdf type="null"/><ref id="medium1" name="interior"/></shape>
    <shape type="cube"><bsdf type="thindielectric"/>
      <medium type="homogeneous" name="exterior"/>
      <ref name="interior" id="medium1"/></shape>)"));
  ASSERT_EQ(s.media.size(), 2u);
  const Medium& m = s.media[0];
  EXPECT_EQ(m.name, "medium1");
  EXPECT_EQ(m.kind, MediumKind::homogeneous);
  EXPECT_EQ(m.sigma_t.value, glm::dvec3(1, 0.2, 1));
  EXPECT_EQ(m.albedo.value, glm::dvec3(0.99, 0.5, 0.5));
  EXPECT_EQ(m.scale, 2.5);
  EXPECT_EQ(m.phase, PhaseKind::hg);
  EXPECT_DOUBLE_EQ(m.g, -0.4);
  EXPECT_FALSE(m.sample_emitters);
  const Medium& d = s.media[1];  // homogeneous.cpp's defaults
  EXPECT_EQ(d.sigma_t.value, glm::dvec3(1));
  EXPECT_EQ(d.albedo.value, glm::dvec3(0.75));
  EXPECT_EQ(d.scale, 1);
  EXPECT_EQ(d.phase, PhaseKind::isotropic);
  EXPECT_TRUE(d.sample_emitters);
  EXPECT_EQ(s.shapes[0].interior, 0);  // one medium for both <ref>s
  EXPECT_EQ(s.shapes[0].exterior, -1);
  EXPECT_EQ(s.shapes[1].interior, 0);
  EXPECT_EQ(s.shapes[1].exterior, 1);
  // hg's default g is 0.8 (src/phase/hg.cpp).
  const Scene hg = parse_xml(mitsuba_scene(std::string(kVolpath) + R"(<shape type="sphere">
      <medium type="homogeneous" name="interior"><phase type="hg"/></medium></shape>)"));
  EXPECT_DOUBLE_EQ(hg.media[0].g, 0.8);
}

TEST(MitsubaMedium, TheSensorsMediumAndConstvolumes) {
  const std::string sensor = R"(<sensor type="perspective"><float name="fov" value="40"/>
      <ref id="fog"/></sensor>)";
  const Scene s = parse_xml(mitsuba_scene(std::string(kVolpath) + R"(
    <medium id="fog" type="homogeneous">
      <volume type="constvolume" name="sigma_t"><rgb name="value" value="0.5, 1, 2"/></volume>
      <float name="albedo" value="0.3"/>
    </medium>)", R"(<medium id="x" type="homogeneous"/>)" + sensor));
  ASSERT_EQ(s.camera.medium, 1);  // "x" first, then "fog"
  EXPECT_EQ(s.media[1].sigma_t.value, glm::dvec3(0.5, 1, 2));
  EXPECT_TRUE(s.media[1].sigma_t.is_constant());
  EXPECT_EQ(s.media[1].albedo.value, glm::dvec3(0.3));
}

TEST(MitsubaMedium, HeterogeneousReadsGridvolumes) {
  const std::string grid = testing::volume_grid_bytes({2, 2, 2}, 1, {0, 1, 2, 3, 4, 5, 6, 7});
  const Scene s = parse_xml(mitsuba_scene(std::string(kVolpath) + R"(<shape type="cube">
      <bsdf type="null"/>
      <medium type="heterogeneous" name="interior">
        <volume type="gridvolume" name="sigma_t"><string name="filename" value="d.vol"/></volume>
        <rgb name="albedo" value="0.9, 0.8, 0.7"/>
        <float name="scale" value="4"/>
      </medium></shape>)"),
                            {{"d.vol", grid}});
  ASSERT_EQ(s.media.size(), 1u);
  EXPECT_EQ(s.media[0].kind, MediumKind::heterogeneous);
  ASSERT_GE(s.media[0].sigma_t.texture, 0);
  EXPECT_EQ(s.textures[size_t(s.media[0].sigma_t.texture)].kind, TextureKind::volume);
  EXPECT_EQ(s.media[0].scale, 4);
  // It survives the trip through the native format (how scenes travel to workers).
  const Scene back = testing::parse(write_scene_json(s), {{"d.vol", grid}});
  ASSERT_EQ(back.media.size(), 1u);
  EXPECT_EQ(back.media[0].kind, MediumKind::heterogeneous);
  EXPECT_EQ(back.shapes[0].interior, 0);
  EXPECT_EQ(back.textures[size_t(back.media[0].sigma_t.texture)].file, "d.vol");
}

TEST(MitsubaMedium, VolumetricIntegratorsAndWhatOthersDoWithMedia) {
  const std::string body = R"(<shape type="sphere"><bsdf type="null"/>
      <medium type="homogeneous" name="interior"/></shape>)";
  // volpathmis (also nested in moment) renders the media.
  for (const char* integrator : {R"(<integrator type="volpathmis"><integer name="max_depth" value="8"/>
                                     <boolean name="use_spectral_mis" value="true"/></integrator>)",
                                 R"(<integrator type="moment"><integrator type="volpath"/></integrator>)"}) {
    const Scene s = parse_xml(mitsuba_scene(integrator + body));
    EXPECT_EQ(s.media.size(), 1u) << integrator;
    EXPECT_EQ(s.shapes[0].interior, 0) << integrator;
  }
  // volpath with a finite max_depth and a null BSDF: accepted with media (the volumetric path
  // tracer counts as volpath does).
  EXPECT_EQ(parse_xml(mitsuba_scene(R"(<integrator type="volpath"><integer name="max_depth" value="4"/></integrator>)" + body))
                .render.max_depth,
            4);
  // Mitsuba's path integrator ignores media: left out.
  const Scene path = parse_xml(mitsuba_scene(R"(<integrator type="path"/>)" + body));
  EXPECT_TRUE(path.media.empty());
  EXPECT_EQ(path.shapes[0].interior, -1);
}

TEST(MitsubaMedium, UnsupportedMediaAreRefusedByName) {
  auto medium_error = [](const std::string& medium) {
    return xml_error(mitsuba_scene(std::string(kVolpath) + "<shape type=\"sphere\">" + medium + "</shape>"));
  };
  EXPECT_NE(medium_error(R"(<medium type="homogeneous" name="interior"><rgb name="sigmaA" value="1"/></medium>)")
                .find("sigmaA"),
            std::string::npos);
  EXPECT_NE(medium_error(R"(<medium type="homogeneous" name="interior"><phase type="rayleigh"/></medium>)")
                .find("<phase type=\"rayleigh\">: unsupported phase function"),
            std::string::npos);
  EXPECT_NE(medium_error(R"(<medium type="homogeneous" name="interior"><phase type="hg">
      <float name="g" value="1"/></phase></medium>)")
                .find("<float name=\"g\">: must be in (-1, 1) (got 1)"),
            std::string::npos)
      << medium_error(R"(<medium type="homogeneous" name="interior"><phase type="hg"><float name="g" value="1"/></phase></medium>)");
  EXPECT_NE(medium_error(R"(<medium type="homogeneous" name="interior"><rgb name="sigma_t" value="-1"/></medium>)")
                .find("sigma_t must be finite and >= 0"),
            std::string::npos);
  EXPECT_NE(medium_error(R"(<medium type="homogeneous" name="interior">
      <boolean name="has_spectral_extinction" value="false"/><rgb name="sigma_t" value="1, 2, 3"/></medium>)")
                .find("has_spectral_extinction"),
            std::string::npos);
  // A grey sigma_t makes has_spectral_extinction irrelevant: accepted.
  EXPECT_EQ(medium_error(R"(<medium type="homogeneous" name="interior">
      <boolean name="has_spectral_extinction" value="false"/><float name="sigma_t" value="2"/></medium>)"),
            "(no error)");
  const std::string grid = testing::volume_grid_bytes({1, 1, 1}, 1, {0.5f});
  EXPECT_NE(xml_error(mitsuba_scene(std::string(kVolpath) + R"(<shape type="sphere">
      <medium type="homogeneous" name="interior"><volume type="gridvolume" name="sigma_t">
      <string name="filename" value="a.vol"/></volume></medium></shape>)"),
                      {{"a.vol", grid}})
                .find("a homogeneous medium's sigma_t is constant"),
            std::string::npos);
  // Its albedo may be a grid (mitsuba-data's docs/scenes/medium_homogeneous_sss_textured.xml).
  const Scene textured = parse_xml(mitsuba_scene(std::string(kVolpath) + R"(<shape type="sphere">
      <medium type="homogeneous" name="interior"><volume type="gridvolume" name="albedo">
      <string name="filename" value="a.vol"/></volume></medium></shape>)"),
                                   {{"a.vol", grid}});
  EXPECT_GE(textured.media[0].albedo.texture, 0);
  EXPECT_NE(medium_error(R"(<medium type="homogeneous" name="interior"/><medium type="homogeneous" name="interior"/>)")
                .find("a second interior medium"),
            std::string::npos);
}

}  // namespace
}  // namespace tessera
