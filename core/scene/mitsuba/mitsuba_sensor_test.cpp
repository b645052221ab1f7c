// Mitsuba sensors: the camera frame, field of view, thin lens, film, filter, sampler,
// integrator and clip planes.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/geometric.hpp>

#include "scene/mitsuba/mitsuba_test_support.h"

namespace tessera {
namespace {

using testing::expect_near;
using testing::kSourceDir;
using testing::line_of;
using testing::mitsuba_scene;
using testing::parse_xml;
using testing::xml_error;

/// A sensor of `type` with `inside` (parameters) and a default film.
std::string sensor(const std::string& inside, const std::string& type = "perspective",
                   const std::string& film = "") {
  return "<sensor type=\"" + type + "\">\n" + inside + "\n" +
         (film.empty() ? "<film type=\"hdrfilm\"><rfilter type=\"box\"/></film>" : film) +
         "\n</sensor>\n";
}

Scene with_sensor(const std::string& s, const std::string& body = "") {
  return parse_xml(mitsuba_scene(body, s));
}

std::string sensor_error(const std::string& s, const std::string& body = "") {
  return xml_error(mitsuba_scene(body, s));
}

/// The camera's image-right direction as Tessera's renderer builds it.
glm::dvec3 image_right(const Camera& c) {
  return glm::normalize(glm::cross(glm::normalize(c.look_at - c.position), c.up));
}

TEST(MitsubaCamera, ReferenceCornellBoxFrame) {
  Scene s = load_scene_file(kSourceDir + "/tests/data/reference/cbox/mitsuba.xml");
  // to_world = [[-1,0,0,0],[0,0.99999994,0,0],[0,0,-0.99999994,3.9000001],[0,0,0,1]]: the local
  // origin, +z and +y.
  EXPECT_EQ(s.camera.position, glm::dvec3(0, 0, 3.9000000953674316));
  EXPECT_EQ(s.camera.look_at, glm::dvec3(0, 0, 3.9000000953674316 - 0.9999999403953552));
  EXPECT_EQ(s.camera.up, glm::dvec3(0, 0.9999999403953552, 0));
  // Mitsuba's image x runs along local -x; here local +x is world -x, so the image's right is
  // world +x, as in scenes/cornell.json.
  expect_near(image_right(s.camera), {1, 0, 0}, 1e-15);
  EXPECT_DOUBLE_EQ(s.camera.fov_deg, 39.3077);
  EXPECT_EQ(s.camera.fov_axis, FovAxis::smaller);
  EXPECT_EQ(s.camera.aperture_radius, 0);  // a pinhole: focus_distance is ignored
}

TEST(MitsubaCamera, MatchesTheNativeCornellBox) {
  Scene xml = load_scene_file(kSourceDir + "/tests/data/reference/cbox/mitsuba.xml");
  Scene json = load_scene_file(kSourceDir + "/scenes/cornell.json");
  expect_near(xml.camera.position, json.camera.position, 1e-7);
  expect_near(glm::normalize(xml.camera.look_at - xml.camera.position),
              glm::normalize(json.camera.look_at - json.camera.position), 1e-7);
  expect_near(image_right(xml.camera), image_right(json.camera), 1e-7);
}

TEST(MitsubaCamera, LookAtGivesTheSameViewAsTessera) {
  Scene s = with_sensor(sensor(R"(<float name="fov" value="45"/>
      <transform name="to_world"><lookat origin="1, 2, 3" target="1, 2, -7" up="0, 1, 0"/>
      </transform>)"));
  expect_near(s.camera.position, {1, 2, 3});
  expect_near(glm::normalize(s.camera.look_at - s.camera.position), {0, 0, -1});
  expect_near(s.camera.up, {0, 1, 0});
  expect_near(image_right(s.camera), {1, 0, 0});  // looking down -z with y up: right is +x
}

TEST(MitsubaCamera, WithoutToWorldItLooksDownPlusZ) {
  Scene s = with_sensor(sensor(R"(<float name="fov" value="45"/>)"));
  expect_near(s.camera.position, {0, 0, 0});
  expect_near(s.camera.look_at, {0, 0, 1});
  expect_near(image_right(s.camera), {-1, 0, 0});  // image x runs along local -x
}

TEST(MitsubaCamera, RotatedFrames) {
  // Turned 90 degrees about y: local +z (the view) becomes world +x, local -x (image right)
  // world +z.
  Scene s = with_sensor(sensor(R"(<float name="fov" value="45"/>
      <transform name="to_world"><rotate y="1" angle="90"/><translate x="1"/></transform>)"));
  expect_near(s.camera.position, {1, 0, 0});
  expect_near(glm::normalize(s.camera.look_at - s.camera.position), {1, 0, 0}, 1e-15);
  expect_near(image_right(s.camera), {0, 0, 1}, 1e-15);
}

TEST(MitsubaCamera, MirroredOrScaledFramesAreRefused) {
  std::string mirror = sensor(R"(<float name="fov" value="45"/>
<transform name="to_world"><scale x="-1"/></transform>)");
  EXPECT_NE(
      sensor_error(mirror).find("test.xml: line " +
                                std::to_string(line_of(mitsuba_scene("", mirror), "<transform")) +
                                ": <transform name=\"to_world\">: this to_world mirrors "
                                "the image"),
      std::string::npos);
  EXPECT_NE(sensor_error(sensor(R"(<float name="fov" value="45"/>
      <transform name="to_world"><scale value="2"/></transform>)"))
                .find("a camera's to_world must be a rotation and a translation"),
            std::string::npos);
}

TEST(MitsubaCamera, FieldOfView) {
  EXPECT_EQ(with_sensor(sensor(R"(<float name="fov" value="30"/>)")).camera.fov_axis, FovAxis::x);
  for (auto [name, axis] : {std::pair{"x", FovAxis::x},
                            {"y", FovAxis::y},
                            {"smaller", FovAxis::smaller},
                            {"larger", FovAxis::larger}}) {
    Scene s = with_sensor(sensor(std::string(R"(<float name="fov" value="30"/>
        <string name="fov_axis" value=")") +
                                 name + "\"/>"));
    EXPECT_EQ(s.camera.fov_axis, axis) << name;
    EXPECT_EQ(s.camera.fov_deg, 30);
  }
  EXPECT_EQ(with_sensor(sensor(R"(<integer name="fov" value="30"/>)")).camera.fov_deg, 30);
}

TEST(MitsubaCamera, RigidityHasMitsubasTolerance) {
  // Bitterli's exports carry rotations rounded to a few digits: rows orthonormal within 1e-3,
  // which Mitsuba accepts.
  EXPECT_NO_THROW(with_sensor(sensor(R"(<float name="fov" value="45"/>
      <transform name="to_world"><matrix value="1.0004 0 0 1  0 1 0 2  0 0 0.9996 3  0 0 0 1"/>
      </transform>)")));
  EXPECT_NE(sensor_error(sensor(R"(<float name="fov" value="45"/>
      <transform name="to_world"><matrix value="1.002 0 0 1  0 1 0 2  0 0 1 3  0 0 0 1"/>
      </transform>)"))
                .find("rows orthonormal within 1e-3"),
            std::string::npos);
}

TEST(MitsubaCamera, DiagonalAndFocalLengthAreMitsubasParseFov) {
  // 64 x 48 film (aspect 4/3): the diagonal angle is kept, and the camera's horizontal extent
  // is what Mitsuba's parse_fov makes of it for the image's aspect: for the film's own, and for
  // another (a job's --width / --height, as Mitsuba at a film of that size).
  Scene diagonal = with_sensor(sensor(R"(<float name="fov" value="30"/>
<string name="fov_axis" value="diagonal"/>)"));
  EXPECT_EQ(diagonal.camera.fov_axis, FovAxis::diagonal);
  EXPECT_EQ(diagonal.camera.fov_deg, 30);
  const double pi = 3.14159265358979323846;
  const auto x_fov = [&](const Camera& c, double aspect) {  // the horizontal angle, degrees
    return 2 * std::atan(fov_half_tangents(c.fov_deg, c.fov_axis, aspect).x) * 180 / pi;
  };
  for (const double aspect : {4.0 / 3, 2.0, 0.5}) {
    const double width = 2 * std::tan(15 * pi / 180) / std::sqrt(1 + 1 / (aspect * aspect));
    EXPECT_NEAR(x_fov(diagonal.camera, aspect), 2 * std::atan(width / 2) * 180 / pi, 1e-12) << aspect;
    EXPECT_NEAR(fov_half_tangents(30, FovAxis::diagonal, aspect).y * aspect, width / 2, 1e-15) << aspect;
  }
  // No fov: Mitsuba's default focal length, 50 mm on a 36 x 24 mm film's diagonal.
  Scene fallback = with_sensor(sensor(""));
  double diagonal_50mm = 2 * std::atan(std::sqrt(36.0 * 36 + 24 * 24) / 100) * 180 / pi;
  double w50 = 2 * std::tan(diagonal_50mm / 2 * pi / 180) / std::sqrt(1 + 1 / (16.0 / 9));
  EXPECT_EQ(fallback.camera.fov_axis, FovAxis::diagonal);
  EXPECT_NEAR(fallback.camera.fov_deg, diagonal_50mm, 1e-12);
  EXPECT_NEAR(x_fov(fallback.camera, 4.0 / 3), 2 * std::atan(w50 / 2) * 180 / pi, 1e-12);
  EXPECT_NEAR(with_sensor(sensor(R"(<string name="focal_length" value="50mm"/>)")).camera.fov_deg,
              fallback.camera.fov_deg, 1e-12);
}

TEST(MitsubaCamera, FieldsOfViewTesseraCannotTakeAreRefused) {
  EXPECT_NE(sensor_error(sensor(R"(<float name="fov" value="30"/>
      <string name="focal_length" value="50mm"/>)"))
                .find("give fov or focal_length, not both"),
            std::string::npos);
  EXPECT_NE(sensor_error(sensor(R"(<string name="focal_length" value="long"/>)"))
                .find("\"long\" is no focal length"),
            std::string::npos);
  EXPECT_NE(sensor_error(sensor(R"(<float name="fov" value="180"/>)")).find("must be in (0, 180)"),
            std::string::npos);
  EXPECT_NE(sensor_error(sensor(R"(<string name="fov" value="wide"/>)"))
                .find("fov must be given as <float>"),
            std::string::npos);
}

TEST(MitsubaCamera, ThinLens) {
  Scene s = with_sensor(sensor(R"(<float name="fov" value="30"/>
      <float name="aperture_radius" value="0.1"/><float name="focus_distance" value="4.5"/>)",
                               "thinlens"));
  EXPECT_EQ(s.camera.aperture_radius, 0.1);
  EXPECT_EQ(s.camera.focus_distance, 4.5);
  // Mitsuba focuses at far_clip unless told otherwise.
  Scene far = with_sensor(sensor(R"(<float name="fov" value="30"/>
      <float name="aperture_radius" value="0.1"/><float name="far_clip" value="50"/>)",
                                 "thinlens"));
  EXPECT_EQ(far.camera.focus_distance, 50);
  EXPECT_NE(sensor_error(sensor(R"(<float name="fov" value="30"/>)", "thinlens"))
                .find("a thinlens sensor needs aperture_radius"),
            std::string::npos);
  EXPECT_NE(sensor_error(sensor(R"(<float name="fov" value="30"/>
      <float name="aperture_radius" value="-1"/>)",
                                "thinlens"))
                .find("must be >= 0"),
            std::string::npos);
  // A perspective camera has no aperture.
  EXPECT_NE(sensor_error(sensor(R"(<float name="fov" value="30"/>
      <float name="aperture_radius" value="0.1"/>)"))
                .find("<float name=\"aperture_radius\">: is not supported in <sensor "
                      "type=\"perspective\">"),
            std::string::npos);
}

TEST(MitsubaCamera, OtherSensorsAreRefused) {
  std::string s = sensor("", "radiancemeter");
  EXPECT_NE(sensor_error(s).find("<sensor type=\"radiancemeter\">: unsupported sensor (Tessera "
                                 "has perspective, thinlens and orthographic cameras)"),
            std::string::npos);
  EXPECT_NE(sensor_error(sensor(R"(<float name="fov" value="30"/>
      <float name="principal_point_offset_x" value="0.1"/>)"))
                .find("the offset must be 0"),
            std::string::npos);
  EXPECT_NO_THROW(with_sensor(sensor(R"(<float name="fov" value="30"/>
      <float name="principal_point_offset_x" value="0"/>
      <float name="shutter_open" value="0"/><float name="shutter_close" value="1"/>)")));
}

TEST(MitsubaFilm, SizeAndAcceptedFormats) {
  Scene s = with_sensor(sensor(R"(<float name="fov" value="30"/>)", "perspective",
                               R"(<film type="hdrfilm"><integer name="width" value="320"/>
      <integer name="height" value="200"/><string name="pixel_format" value="rgba"/>
      <string name="component_format" value="float16"/><string name="file_format" value="openexr"/>
      <boolean name="sample_border" value="true"/><integer name="crop_offset_x" value="0"/>
      <integer name="crop_width" value="320"/><rfilter type="box"/></film>)"));
  EXPECT_EQ(s.film.width, 320);
  EXPECT_EQ(s.film.height, 200);
  Scene defaults = with_sensor(sensor(R"(<float name="fov" value="30"/>)"));
  EXPECT_EQ(defaults.film.width, 768);  // Mitsuba's hdrfilm defaults
  EXPECT_EQ(defaults.film.height, 576);
}

TEST(MitsubaFilm, BooleansMitsubaIgnoresAreAccepted) {
  auto film_of = [](const std::string& inside) {
    return sensor(R"(<float name="fov" value="30"/>)", "perspective",
                  "<film type=\"hdrfilm\"><integer name=\"width\" value=\"32\"/>" + inside +
                      "<rfilter type=\"box\"/></film>");
  };
  const Scene plain = with_sensor(film_of(""));
  for (const char* value : {"true", "false"}) {
    const Scene s = with_sensor(film_of(std::string("<boolean name=\"banner\" value=\"") + value +
                                        "\"/><boolean name=\"compensate\" value=\"" + value +
                                        "\"/>"));
    EXPECT_EQ(s.film.width, plain.film.width);
    EXPECT_EQ(s.film.height, plain.film.height);
    EXPECT_EQ(s.film.filter.kind, plain.film.filter.kind);
  }
  // Still booleans: anything else is refused.
  EXPECT_NE(sensor_error(film_of(R"(<boolean name="banner" value="maybe"/>)")).find("banner"),
            std::string::npos);
  // Mitsuba 0.6's high_quality_edges, which Mitsuba 3 refuses as well.
  EXPECT_NE(sensor_error(film_of(R"(<boolean name="high_quality_edges" value="true"/>)"))
                .find("<boolean name=\"high_quality_edges\">: Mitsuba 0.6's parameter, which "
                      "Mitsuba 3 refuses too"),
            std::string::npos);
}

TEST(MitsubaFilm, ReconstructionFilters) {
  auto filter_of = [](const std::string& film) {
    return with_sensor(sensor(R"(<float name="fov" value="30"/>)", "perspective", film))
        .film.filter;
  };
  PixelFilter box = filter_of(R"(<film type="hdrfilm"><rfilter type="box"/></film>)");
  EXPECT_EQ(box.kind, FilterKind::box);
  EXPECT_EQ(box.radius, 0.5);
  PixelFilter tent = filter_of(R"(<film type="hdrfilm"><rfilter type="tent"/></film>)");
  EXPECT_EQ(tent.kind, FilterKind::tent);
  EXPECT_EQ(tent.radius, 1.0);
  PixelFilter gauss = filter_of(R"(<film type="hdrfilm"><rfilter type="gaussian">
      <float name="stddev" value="0.25"/></rfilter></film>)");
  EXPECT_EQ(gauss.kind, FilterKind::gaussian);
  EXPECT_EQ(gauss.stddev, 0.25);
  EXPECT_EQ(gauss.radius, 1.0);  // Mitsuba truncates at 4 stddev
  PixelFilter mitchell = filter_of(R"(<film type="hdrfilm"><rfilter type="mitchell"/></film>)");
  EXPECT_EQ(mitchell.kind, FilterKind::mitchell);
  EXPECT_EQ(mitchell.radius, 2.0);
  EXPECT_EQ(mitchell.b, 1.0 / 3);
  EXPECT_EQ(mitchell.c, 1.0 / 3);
  mitchell = filter_of(R"(<film type="hdrfilm"><rfilter type="mitchell">
      <float name="B" value="0.5"/><float name="C" value="0.25"/></rfilter></film>)");
  EXPECT_EQ(mitchell.b, 0.5);
  EXPECT_EQ(mitchell.c, 0.25);
  PixelFilter catmullrom = filter_of(R"(<film type="hdrfilm"><rfilter type="catmullrom"/></film>)");
  EXPECT_EQ(catmullrom.kind, FilterKind::mitchell);
  EXPECT_EQ(catmullrom.b, 0.0);
  EXPECT_EQ(catmullrom.c, 0.5);
  PixelFilter lanczos = filter_of(R"(<film type="hdrfilm"><rfilter type="lanczos"/></film>)");
  EXPECT_EQ(lanczos.kind, FilterKind::lanczos);
  EXPECT_EQ(lanczos.radius, 3.0);  // Mitsuba's default of 3 lobes
  lanczos = filter_of(R"(<film type="hdrfilm"><rfilter type="lanczos"><integer name="lobes" value="2"/>
      </rfilter></film>)");
  EXPECT_EQ(lanczos.radius, 2.0);
  // Without <rfilter>, and without <film>, Mitsuba's default: gaussian, stddev 0.5.
  for (const std::string& film : {std::string(R"(<film type="hdrfilm"/>)"), std::string()}) {
    PixelFilter fallback = film.empty()
                               ? with_sensor("<sensor type=\"perspective\"><float name=\"fov\" "
                                             "value=\"30\"/></sensor>")
                                     .film.filter
                               : filter_of(film);
    EXPECT_EQ(fallback.kind, FilterKind::gaussian);
    EXPECT_EQ(fallback.stddev, 0.5);
    EXPECT_EQ(fallback.radius, 2.0);
  }
}

TEST(MitsubaFilm, WhatChangesTheImageIsRefused) {
  auto film_error = [](const std::string& film) {
    return sensor_error(sensor(R"(<float name="fov" value="30"/>)", "perspective", film));
  };
  EXPECT_NE(film_error(R"(<film type="hdrfilm"><rfilter type="sinc"/></film>)")
                .find("<rfilter type=\"sinc\">: unsupported reconstruction filter (Tessera "
                      "has box, tent, gaussian, mitchell, catmullrom and lanczos)"),
            std::string::npos);
  EXPECT_NE(film_error(R"(<film type="hdrfilm"><rfilter type="lanczos"><integer name="lobes" value="0"/>
      </rfilter></film>)")
                .find("<integer name=\"lobes\">: must be a whole number from 1 to 64 (got 0)"),
            std::string::npos);
  EXPECT_NE(film_error(R"(<film type="hdrfilm"><rfilter type="mitchell"><float name="A" value="0.25"/>
      </rfilter></film>)")
                .find("\"A\""),
            std::string::npos);  // Mitsuba's docs name A and B; its code reads B and C
  EXPECT_NE(film_error(R"(<film type="hdrfilm"><rfilter type="box"><float name="radius" value="0"/>
      </rfilter></film>)")
                .find("<float name=\"radius\">: must be > 0 (got 0)"),
            std::string::npos);
  EXPECT_NE(film_error(R"(<film type="hdrfilm"><string name="pixel_format" value="luminance"/>
      <rfilter type="box"/></film>)")
                .find("\"luminance\": Tessera renders RGB"),
            std::string::npos);
  EXPECT_NE(film_error(R"(<film type="hdrfilm"><integer name="crop_width" value="10"/>
      <rfilter type="box"/></film>)")
                .find("remove the crop window"),
            std::string::npos);
  EXPECT_NE(
      film_error(R"(<film type="specfilm"><rfilter type="box"/></film>)").find("unsupported film"),
      std::string::npos);
  EXPECT_NE(film_error(R"(<film type="hdrfilm"><integer name="width" value="0"/>
      <rfilter type="box"/></film>)")
                .find("must be in [1, 32768] (got 0)"),
            std::string::npos);
}

TEST(MitsubaSampler, CountAndSeed) {
  Scene s = with_sensor(sensor(R"(<float name="fov" value="30"/>
      <sampler type="stratified"><integer name="sample_count" value="100"/>
      <integer name="seed" value="7"/><boolean name="jitter" value="false"/></sampler>)"));
  EXPECT_EQ(s.render.spp, 100);
  EXPECT_EQ(s.render.seed, 7u);
  EXPECT_EQ(with_sensor(sensor(R"(<float name="fov" value="30"/>)")).render.spp, 4);  // default
  EXPECT_NE(sensor_error(sensor(R"(<float name="fov" value="30"/><sampler type="sobol"/>)"))
                .find("unknown sampler"),
            std::string::npos);
  EXPECT_NE(sensor_error(sensor(R"(<float name="fov" value="30"/><sampler type="independent">
      <integer name="sample_count" value="0"/></sampler>)"))
                .find("must be >= 1"),
            std::string::npos);
  EXPECT_NE(sensor_error(sensor(R"(<float name="fov" value="30"/><sampler type="independent">
      <float name="sample_count" value="4"/></sampler>)"))
                .find("sample_count must be given as <integer>"),
            std::string::npos);
}

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

TEST(MitsubaClipPlanes, AcceptedWhenTheyHideNothing) {
  // The camera at z = 5 looks at a rectangle at the origin: nothing nearer than 4, nothing
  // farther than 6.
  std::string body = R"(<shape type="rectangle"/>)";
  EXPECT_NO_THROW(parse_xml(mitsuba_scene(body, sensor(R"(<float name="fov" value="40"/>
      <float name="near_clip" value="3.9"/><float name="far_clip" value="6.1"/>
      <transform name="to_world"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform>
      )"))));
  // Geometry behind the camera or outside the frustum is not clipped in view.
  std::string beside = R"(<shape type="sphere"><point name="center" value="0, 0, 9"/></shape>
      <shape type="sphere"><point name="center" value="500, 0, -500"/></shape>)";
  EXPECT_NO_THROW(parse_xml(mitsuba_scene(beside, sensor(R"(<float name="fov" value="40"/>
      <float name="far_clip" value="100"/>
      <transform name="to_world"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform>
      )"))));
}

TEST(MitsubaClipPlanes, ACameraInsideARoomOrASkySphereIsFine) {
  // Walls reach behind and beside the camera, and the sky sphere encloses it: no surface is
  // within near_clip in view, nor beyond far_clip.
  std::string room = R"(<shape type="cube"><boolean name="flip_normals" value="true"/>
      <transform name="to_world"><scale value="3"/></transform></shape>
      <shape type="sphere"><float name="radius" value="50"/>
      <boolean name="flip_normals" value="true"/></shape>)";
  EXPECT_NO_THROW(parse_xml(mitsuba_scene(room, sensor(R"(<float name="fov" value="60"/>
      <float name="near_clip" value="0.1"/><float name="far_clip" value="80"/>
      <transform name="to_world"><lookat origin="0,0.5,2.8" target="0,0,0" up="0,1,0"/></transform>
      )"))));
  // A wall 0.05 in front of the camera is hidden by a near_clip of 0.1.
  EXPECT_NE(xml_error(mitsuba_scene(room, sensor(R"(<float name="fov" value="60"/>
      <float name="near_clip" value="0.1"/>
      <transform name="to_world"><lookat origin="0,0,-2.95" target="0,0,-5" up="0,1,0"/></transform>
      )")))
                .find("near_clip 0.1 could hide part of test.xml"),
            std::string::npos);
}

TEST(MitsubaClipPlanes, AThinLensSeesFromItsWholeAperture) {
  // A sphere beside the pinhole's cone beyond far_clip, but within reach of rays from the edge
  // of a wide aperture.
  std::string body = R"(<shape type="sphere"><point name="center" value="1.2, 0, -20"/>
      <float name="radius" value="0.1"/></shape>)";
  std::string lens = R"(<float name="fov" value="1"/><float name="far_clip" value="10"/>
      <transform name="to_world"><lookat origin="0,0,0" target="0,0,-1" up="0,1,0"/></transform>)";
  EXPECT_NO_THROW(parse_xml(mitsuba_scene(body, sensor(lens + R"(
      <float name="aperture_radius" value="0.001"/>)",
                                                       "thinlens"))));
  EXPECT_NE(xml_error(mitsuba_scene(body, sensor(lens + R"(
      <float name="aperture_radius" value="1"/><float name="focus_distance" value="5"/>)",
                                                 "thinlens")))
                .find("far_clip 10 could hide part of"),
            std::string::npos);
}

TEST(MitsubaClipPlanes, RefusedWhenTheyCouldHideGeometry) {
  std::string body = "\n<shape type=\"rectangle\"/>";
  std::string near = sensor(R"(<float name="fov" value="40"/><float name="near_clip" value="5.5"/>
      <transform name="to_world"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform>)");
  std::string xml = mitsuba_scene(body, near);
  EXPECT_EQ(xml_error(xml),
            "test.xml: line 2: <sensor type=\"perspective\">: near_clip 5.5 could "
            "hide part of test.xml: line " +
                std::to_string(line_of(xml, "<shape")) +
                ": <shape type=\"rectangle\">, and Tessera does not clip: lower "
                "near_clip");
  std::string far = sensor(R"(<float name="fov" value="40"/><float name="far_clip" value="4.5"/>
      <transform name="to_world"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform>)");
  EXPECT_NE(xml_error(mitsuba_scene(body, far)).find("far_clip 4.5 could hide part of"),
            std::string::npos);
  // Mitsuba's default far_clip, 10^4, applies when none is given.
  std::string huge = R"(<shape type="sphere"><point name="center" value="0, 0, -20000"/>
      <float name="radius" value="100"/></shape>)";
  EXPECT_NE(xml_error(mitsuba_scene(huge)).find("far_clip 10000 could hide part of"),
            std::string::npos);
  EXPECT_NE(sensor_error(sensor(R"(<float name="fov" value="40"/><float name="near_clip" value="2"/>
      <float name="far_clip" value="1"/>)"))
                .find("near_clip must be smaller than far_clip"),
            std::string::npos);
}

TEST(MitsubaCamera, OrthographicViewComesFromTheScale) {
  // Mitsuba's documented form: the scale first, then lookat. The view covers local x in
  // [-1, 1] and y in [-1, 1] / aspect; rays start at near_clip, scaled by z.
  Scene s = with_sensor(sensor(R"(<float name="near_clip" value="0.5"/>
      <transform name="to_world"><scale x="10" y="4" z="2"/>
        <lookat origin="1, 1, 1" target="1, 2, 1" up="0, 0, 1"/></transform>)",
                               "orthographic",
                               R"(<film type="hdrfilm"><integer name="width" value="40"/>
        <integer name="height" value="20"/><rfilter type="box"/></film>)"));
  EXPECT_EQ(s.camera.projection, Projection::orthographic);
  expect_near(s.camera.position, {1, 2, 1}, 1e-12);
  expect_near(glm::normalize(s.camera.look_at - s.camera.position), {0, 1, 0}, 1e-12);
  expect_near(s.camera.up, {0, 0, 1}, 1e-12);
  EXPECT_DOUBLE_EQ(s.camera.view_size.x, 20);
  EXPECT_DOUBLE_EQ(s.camera.view_size.y, 4);
  // Made for the film's aspect, which the view's height follows at another image size.
  EXPECT_DOUBLE_EQ(s.camera.view_aspect, 2);
  // Without to_world: camera space, the default near_clip 0.01.
  Scene plain = with_sensor(sensor("", "orthographic"));
  expect_near(plain.camera.position, {0, 0, 0.01}, 1e-15);
  EXPECT_DOUBLE_EQ(plain.camera.view_size.x, 2);
  EXPECT_DOUBLE_EQ(plain.camera.view_size.y, 2 * 576.0 / 768.0);
}

TEST(MitsubaCamera, OrthographicRefusals) {
  // lookat then scale scales the world's axes: the view is sheared.
  std::string sheared = sensor(R"(<transform name="to_world">
        <lookat origin="0, 0, 0" target="1, 0, 1" up="0, 1, 0"/><scale x="3"/></transform>)",
                               "orthographic");
  EXPECT_NE(sensor_error(sheared).find("<transform name=\"to_world\">: an orthographic camera's "
                                       "to_world must be a rotation of a scale"),
            std::string::npos)
      << sensor_error(sheared);
  EXPECT_NE(sensor_error(sensor(R"(<transform name="to_world"><scale x="-1"/></transform>)",
                                "orthographic"))
                .find("mirrors the image"),
            std::string::npos);
  EXPECT_NE(sensor_error(sensor(R"(<float name="fov" value="30"/>)", "orthographic"))
                .find("<float name=\"fov\">: is not supported in <sensor type=\"orthographic\">"),
            std::string::npos);
  // far_clip hides a wall that Tessera's camera would see.
  std::string far = sensor(R"(<float name="far_clip" value="5"/>
      <transform name="to_world"><scale x="2" y="2" z="4"/></transform>)",
                           "orthographic");
  std::string wall = R"(<shape type="rectangle"><transform name="to_world">
        <translate z="5"/></transform></shape>)";
  EXPECT_NO_THROW(with_sensor(far, wall));  // rays end at z = 0.01 * 4 + (5 - 0.01) = 5.03
  std::string beyond = R"(<shape type="rectangle"><transform name="to_world">
        <translate x="2.5" z="5.1"/></transform></shape>)";
  EXPECT_NE(sensor_error(far, beyond).find("far_clip 5 could hide part of"), std::string::npos)
      << sensor_error(far, beyond);
  // Beside the view (x beyond 2 + 1) it is not seen at all.
  std::string beside = R"(<shape type="rectangle"><transform name="to_world">
        <translate x="3.5" z="5.1"/></transform></shape>)";
  EXPECT_NO_THROW(with_sensor(far, beside));
}

}  // namespace
}  // namespace tessera
