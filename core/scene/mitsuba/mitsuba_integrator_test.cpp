// Mitsuba integrators: those Tessera renders as its path tracer, their depths and flags, and the
// nested integrators of moment and aov.
#include <gtest/gtest.h>

#include "scene/mitsuba/mitsuba_test_support.h"

namespace tessera {
namespace {

using testing::line_of;
using testing::mitsuba_scene;
using testing::parse_xml;
using testing::xml_error;

TEST(MitsubaIntegrator, ThoseThatRenderThePathImageAreAccepted) {
  auto with_integrator = [](const std::string& integrator) {
    return parse_xml(mitsuba_scene(integrator));
  };
  Scene ptracer = with_integrator(R"(<integrator type="ptracer">
      <integer name="max_depth" value="5"/><integer name="samples_per_pass" value="4"/>
      <boolean name="hide_emitters" value="true"/></integrator>)");
  EXPECT_EQ(ptracer.render.max_depth, 5);
  EXPECT_TRUE(ptracer.render.hide_emitters);
  EXPECT_EQ(with_integrator(R"(<integrator type="volpath"><integer name="max_depth" value="3"/>
      </integrator>)")
                .render.max_depth,
            3);
  // direct: emitters seen by the camera and one bounce of light, path's max_depth 2.
  EXPECT_EQ(with_integrator(R"(<integrator type="direct">
      <integer name="emitter_samples" value="4"/></integrator>)")
                .render.max_depth,
            2);
}

// Mitsuba's volpath counts only non-null BSDF samples toward max_depth (volpath.cpp); its path
// integrator and Tessera count every hit. With a mask, a null BSDF or a thindielectric (its
// transmission is a null interaction) and a finite max_depth the images differ: refused, unless
// max_depth is unbounded.
TEST(MitsubaIntegrator, VolpathWithNullInteractionsNeedsAnUnboundedDepth) {
  const std::string volpath = R"(<integrator type="volpath">
      <integer name="max_depth" value="6"/></integrator>)";
  for (const char* bsdf : {R"(<bsdf type="null"/>)", R"(<bsdf type="thindielectric"/>)",
                           R"(<bsdf type="mask"><bsdf type="diffuse"/></bsdf>)",
                           R"(<bsdf type="blendbsdf"><float name="weight" value="0.5"/>
                              <bsdf type="thindielectric"/><bsdf type="diffuse"/></bsdf>)"}) {
    const std::string xml =
        mitsuba_scene(volpath + "<shape type=\"rectangle\">" + bsdf + "</shape>");
    EXPECT_NE(xml_error(xml).find("line " + std::to_string(line_of(xml, "<integrator")) +
                                  ": <integrator type=\"volpath\">: volpath with max_depth 6 "
                                  "and material \""),
              std::string::npos)
        << xml_error(xml);
    EXPECT_NE(xml_error(xml).find("write max_depth -1 or the path integrator"), std::string::npos);
    // Unbounded, or under path, the same scene is accepted.
    EXPECT_EQ(xml_error(mitsuba_scene(R"(<integrator type="volpath"/><shape type="rectangle">)" +
                                      std::string(bsdf) + "</shape>")),
              "(no error)");
    EXPECT_EQ(xml_error(mitsuba_scene(R"(<integrator type="path"><integer name="max_depth"
        value="6"/></integrator><shape type="rectangle">)" + std::string(bsdf) + "</shape>")),
              "(no error)");
  }
}

// direct_projective's primal image is Mitsuba's direct illumination (one emitter sample, MIS with
// BSDF sampling, max_depth forced to 2 whatever is written); its options steer gradients only.
TEST(MitsubaIntegrator, DirectProjectiveRendersAsDirect) {
  Scene s = parse_xml(mitsuba_scene(R"(<integrator type="direct_projective">
      <integer name="max_depth" value="7"/><integer name="rr_depth" value="3"/>
      <integer name="sppc" value="32"/><integer name="sppp" value="16"/>
      <integer name="sppi" value="128"/><string name="guiding" value="grid"/>
      <boolean name="guiding_proj" value="false"/><integer name="guiding_rounds" value="2"/>
      <string name="project_seed" value="bsdf"/><boolean name="hide_emitters" value="true"/>
      </integrator>)"));
  EXPECT_EQ(s.render.max_depth, 2);
  EXPECT_TRUE(s.render.hide_emitters);
  EXPECT_EQ(parse_xml(mitsuba_scene(R"(<integrator type="direct_projective"/>)")).render.max_depth,
            2);
  auto error = [](const std::string& integrator) { return xml_error(mitsuba_scene(integrator)); };
  EXPECT_NE(error(R"(<integrator type="direct_projective"><string name="guiding" value="kd"/>
      </integrator>)")
                .find("must be one of none, grid, octree (got \"kd\")"),
            std::string::npos)
      << error(R"(<integrator type="direct_projective"><string name="guiding" value="kd"/>
      </integrator>)");
  EXPECT_NE(error(R"(<integrator type="direct_projective"><integer name="rr_depth" value="0"/>
      </integrator>)")
                .find("must be > 0 (got 0)"),
            std::string::npos);
  EXPECT_NE(error(R"(<integrator type="direct_projective"><float name="sppc" value="2"/>
      </integrator>)"),
            "");
  EXPECT_NE(error(R"(<integrator type="direct_projective"><integer name="spp" value="2"/>
      </integrator>)")
                .find("spp"),
            std::string::npos);
}

// Mitsuba 3.9.1's direct integrator counts each of its emitter_samples samples of a delta light
// at full weight: mitsuba-data's scenes/hello.xml (two point lights, emitter_samples 4,
// bsdf_samples 0) has image mean 0.0519 in Mitsuba, 0.0129 with emitter_samples 1, and 0.0120 in
// Tessera (96 x 72, scalar_rgb; 0.0259 and 0.0388 with emitter_samples 2 and 3, bsdf_samples 2
// and 1). Refused rather than rendered N times darker than Mitsuba.
TEST(MitsubaIntegrator, DirectWithSeveralSamplesOfADeltaLightIsRefused) {
  const std::string point = R"(<emitter type="point"><point name="position" x="0" y="0" z="3"/>
      </emitter>)";
  const std::string sphere = R"(<shape type="sphere"><emitter type="area"/></shape>)";
  auto direct = [](const std::string& samples, const std::string& lights) {
    return mitsuba_scene("<integrator type=\"direct\">" + samples + "</integrator>" + lights);
  };
  std::string error =
      xml_error(direct(R"(<integer name="emitter_samples" value="4"/>
      <integer name="bsdf_samples" value="0"/>)", point));
  EXPECT_NE(error.find("test.xml: line "), std::string::npos) << error;
  EXPECT_NE(error.find("<integrator type=\"direct\">: the direct integrator with 4 emitter "
                       "samples and a point, spot, directional or projector light"),
            std::string::npos)
      << error;
  EXPECT_NE(xml_error(direct(R"(<integer name="emitter_samples" value="2"/>
      <integer name="bsdf_samples" value="2"/>)", point))
                .find("with 2 emitter samples"),
            std::string::npos);
  // Mitsuba weighs these right: one emitter sample, shading_samples alone (hello.xml with
  // shading_samples 3: 0.0129), several samples of an area light.
  EXPECT_EQ(parse_xml(direct(R"(<integer name="shading_samples" value="3"/>)", point))
                .render.max_depth,
            2);
  EXPECT_EQ(parse_xml(direct(R"(<integer name="emitter_samples" value="1"/>
      <integer name="shading_samples" value="4"/>)", point)).render.max_depth, 2);
  EXPECT_EQ(parse_xml(direct(R"(<integer name="emitter_samples" value="4"/>)", sphere))
                .render.max_depth,
            2);
}

TEST(MitsubaIntegrator, PathDepthAndFlags) {
  auto with_integrator = [](const std::string& integrator) {
    return parse_xml(mitsuba_scene(integrator));
  };
  EXPECT_EQ(with_integrator("").render.max_depth, -1);  // Mitsuba's default: path, unbounded
  EXPECT_EQ(with_integrator(R"(<integrator type="path"/>)").render.max_depth, -1);
  Scene s = with_integrator(R"(<integrator type="path"><integer name="max_depth" value="8"/>
      <integer name="rr_depth" value="3"/><boolean name="hide_emitters" value="false"/>
      </integrator>)");
  EXPECT_EQ(s.render.max_depth, 8);
  auto error = [](const std::string& integrator) { return xml_error(mitsuba_scene(integrator)); };
  EXPECT_FALSE(s.render.hide_emitters);
  EXPECT_TRUE(with_integrator(R"(<integrator type="path">
      <boolean name="hide_emitters" value="true"/></integrator>)")
                  .render.hide_emitters);
  EXPECT_NE(error(R"(<integrator type="path"><integer name="max_depth" value="0"/></integrator>)")
                .find("must be -1 (unbounded) or >= 1 (got 0)"),
            std::string::npos);
  EXPECT_NE(error(R"(<integrator type="bdpt"/>)").find("unsupported integrator"),
            std::string::npos);
  EXPECT_NE(error(R"(<integrator type="stokes"/>)").find("makes another kind of image"),
            std::string::npos);
  EXPECT_NE(error(R"(<integrator type="prbvolpath"/>)").find("unsupported integrator"),
            std::string::npos);
  EXPECT_NE(
      error(R"(<integrator type="path"/><integrator type="path"/>)").find("a second integrator"),
      std::string::npos);
}

// Mitsuba's ptracer connects each surface it reaches to the camera: a smooth lobe has no value
// toward it and a see-through surface blocks the connection, so smooth glass and mirrors the
// camera sees are black there. The note names the scene's such materials, and only then says
// the images differ.
TEST(MitsubaIntegrator, PtracerNoteNamesTheSmoothSurfacesItCannotShow) {
  auto note = [](const std::string& shapes) {
    ::testing::internal::CaptureStderr();
    parse_xml(mitsuba_scene(R"(<integrator type="ptracer"/>)" + shapes));
    return ::testing::internal::GetCapturedStderr();
  };
  const std::string diffuse = note(R"(<shape type="sphere"><bsdf type="diffuse"/></shape>
      <shape type="rectangle"><bsdf type="roughconductor"/></shape>)");
  EXPECT_NE(diffuse.find("the ptracer integrator is rendered by Tessera's path tracer (other "
                         "noise); the same image (the scene has no smooth or see-through "
                         "surface)"),
            std::string::npos)
      << diffuse;
  EXPECT_EQ(diffuse.find("black"), std::string::npos) << diffuse;
  const std::string smooth = note(R"(<bsdf type="dielectric" id="glass"/>
      <shape type="sphere"><ref id="glass"/></shape>
      <shape type="rectangle"><bsdf type="conductor"/></shape>
      <shape type="cube"><bsdf type="diffuse" id="unused_by_the_note"/></shape>)");
  EXPECT_NE(smooth.find("(other noise); not the same image on the smooth or see-through "
                        "surfaces the camera sees, directly or through other smooth ones"),
            std::string::npos)
      << smooth;
  EXPECT_NE(smooth.find("so it leaves them black"), std::string::npos) << smooth;
  EXPECT_NE(smooth.find("such materials here: \"glass\", \"conductor (test.xml line "),
            std::string::npos)
      << smooth;
  EXPECT_EQ(smooth.find("unused_by_the_note"), std::string::npos) << smooth;
  // See-through surfaces block the particle tracer's connection to the camera too; a path
  // integrator gets no such note.
  EXPECT_NE(note(R"(<shape type="rectangle"><bsdf type="mask" id="leaf"><bsdf type="diffuse"/>
      </bsdf></shape>)").find("such materials here: \"leaf\""),
            std::string::npos);
  ::testing::internal::CaptureStderr();
  parse_xml(mitsuba_scene(R"(<integrator type="path"/><shape type="sphere">
      <bsdf type="dielectric"/></shape>)"));
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
}

// rr_depth says where Russian roulette starts (mitsuba-data's bsdf_dielectric_diamond.xml writes
// 1000: none). Mitsuba's path applies it from depth rr_depth on, volpath, volpathmis and ptracer
// past it; Tessera's rr_depth counts as path does.
TEST(MitsubaIntegrator, RrDepthSaysWhereRussianRouletteStarts) {
  auto rr_depth = [](const std::string& type, const std::string& value) {
    return parse_xml(mitsuba_scene("<integrator type=\"" + type +
                                   "\"><integer name=\"rr_depth\" value=\"" + value +
                                   "\"/></integrator>"))
        .render.rr_depth;
  };
  EXPECT_EQ(rr_depth("path", "1000"), 1000);
  EXPECT_EQ(rr_depth("path", "1"), 1);
  EXPECT_EQ(rr_depth("volpath", "1000"), 1001);
  EXPECT_EQ(rr_depth("volpathmis", "5"), 6);
  EXPECT_EQ(rr_depth("ptracer", "5"), 6);
  EXPECT_EQ(rr_depth("path", "99999999999"), 2147483646);
  EXPECT_EQ(parse_xml(mitsuba_scene(R"(<integrator type="moment"><integrator type="path">
      <integer name="rr_depth" value="7"/></integrator></integrator>)"))
                .render.rr_depth,
            7);
  // Absent: Tessera's own start (noise only; Mitsuba's default would be 5).
  EXPECT_EQ(parse_xml(mitsuba_scene(R"(<integrator type="path"/>)")).render.rr_depth,
            kDefaultRrDepth);
  EXPECT_EQ(parse_xml(mitsuba_scene("")).render.rr_depth, kDefaultRrDepth);
  const std::string xml = mitsuba_scene(R"(<integrator type="path">
      <integer name="rr_depth" value="0"/></integrator>)");
  EXPECT_EQ(xml_error(xml), "test.xml: line " + std::to_string(line_of(xml, "rr_depth")) +
                                ": <integer name=\"rr_depth\">: must be > 0 (got 0)");
}

// moment's R, G, B are its first nested integrator's picture (Mitsuba 3.9.1: bit for bit that
// integrator's image alone, same seed); its AOV channels are not written.
TEST(MitsubaIntegrator, MomentRendersItsFirstNestedIntegrator) {
  auto with_integrator = [](const std::string& integrator) {
    return parse_xml(mitsuba_scene(integrator));
  };
  Scene s = with_integrator(R"(<integrator type="moment"><integrator type="path">
      <integer name="max_depth" value="5"/><boolean name="hide_emitters" value="true"/>
      </integrator></integrator>)");
  EXPECT_EQ(s.render.max_depth, 5);
  EXPECT_TRUE(s.render.hide_emitters);
  EXPECT_EQ(with_integrator(R"(<integrator type="moment"><integrator type="direct"/>
      <integrator type="path"/></integrator>)")
                .render.max_depth,
            2);
  EXPECT_EQ(with_integrator(R"(<integrator type="moment"><integrator type="path"/>
      <integrator type="direct"/></integrator>)")
                .render.max_depth,
            -1);
  // The moment integrator's own hide_emitters changes nothing: its nested integrators sample.
  EXPECT_FALSE(with_integrator(R"(<integrator type="moment">
      <boolean name="hide_emitters" value="true"/><integrator type="path"/></integrator>)")
                   .render.hide_emitters);
  auto error = [](const std::string& integrator) { return xml_error(mitsuba_scene(integrator)); };
  EXPECT_NE(error(R"(<integrator type="moment"/>)").find("needs a nested integrator"),
            std::string::npos);
  EXPECT_NE(error(R"(<integrator type="moment"><integrator type="bdpt"/></integrator>)")
                .find("<integrator type=\"bdpt\">: unsupported integrator"),
            std::string::npos)
      << error(R"(<integrator type="moment"><integrator type="bdpt"/></integrator>)");
  EXPECT_NE(error(R"(<integrator type="moment"><integrator type="path">
      <integer name="max_depth" value="0"/></integrator></integrator>)")
                .find("must be -1 (unbounded) or >= 1 (got 0)"),
            std::string::npos);
  EXPECT_NE(error(R"(<integrator type="moment"><integer name="max_depth" value="3"/>
      <integrator type="path"/></integrator>)")
                .find("max_depth"),
            std::string::npos);
}

// aov's R, G, B are its first nested integrator's picture too (Mitsuba 3.9.1, measured on
// docs/scenes/integrator_aov.xml); without a nested integrator its image is the AOVs alone.
TEST(MitsubaIntegrator, AovRendersItsFirstNestedIntegrator) {
  auto with_integrator = [](const std::string& integrator) {
    return parse_xml(mitsuba_scene(integrator));
  };
  Scene s = with_integrator(R"(<integrator type="aov">
      <string name="aovs" value="nn:sh_normal, position:position,depth.y:depth,"/>
      <integrator type="path" name="image"><integer name="max_depth" value="6"/></integrator>
      <integrator type="direct"/></integrator>)");
  EXPECT_EQ(s.render.max_depth, 6);
  EXPECT_EQ(with_integrator(R"(<integrator type="aov"><string name="aovs" value="a:albedo"/>
      <integrator type="direct"/><integrator type="path"/></integrator>)")
                .render.max_depth,
            2);
  auto error = [](const std::string& integrator) { return xml_error(mitsuba_scene(integrator)); };
  EXPECT_NE(error(R"(<integrator type="aov"><string name="aovs" value="nn:sh_normal"/>
      </integrator>)")
                .find("needs a nested integrator (without one its image is the AOVs alone"),
            std::string::npos);
  EXPECT_NE(error(R"(<integrator type="aov"><string name="aovs" value="nn:normals"/>
      <integrator type="path"/></integrator>)")
                .find("unknown AOV type \"normals\""),
            std::string::npos);
  EXPECT_NE(error(R"(<integrator type="aov"><string name="aovs" value="nn:sh_normal, depth"/>
      <integrator type="path"/></integrator>)")
                .find("\"depth\" is not a <name>:<type> pair"),
            std::string::npos);
  EXPECT_NE(error(R"(<integrator type="aov"><string name="aovs" value="a:depth"/>
      <integrator type="bdpt"/></integrator>)")
                .find("<integrator type=\"bdpt\">: unsupported integrator"),
            std::string::npos);
}

}  // namespace
}  // namespace tessera
