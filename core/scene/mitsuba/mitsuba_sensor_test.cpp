// Mitsuba sensors: the camera frame, field of view, thin lens, orthographic view and clip planes
// (film and sampler: mitsuba_film_test.cpp; integrators: mitsuba_integrator_test.cpp).
#include <gtest/gtest.h>

#include <cmath>

#include <glm/geometric.hpp>

#include "scene/mitsuba/mitsuba_sensor_test_support.h"
#include "scene/mitsuba/mitsuba_test_support.h"

namespace tessera {
namespace {

using testing::expect_near;
using testing::image_right;
using testing::line_of;
using testing::mitsuba_scene;
using testing::parse_xml;
using testing::sensor;
using testing::sensor_error;
using testing::with_sensor;
using testing::xml_error;

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
