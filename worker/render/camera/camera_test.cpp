// The cameras against Mitsuba 3's rays (reference values from mitsuba_camera_reference.py, in
// mitsuba_camera_reference.inc): Mitsuba's sensors read by the importer, turned into
// Tessera's camera, must start and aim every ray as Mitsuba's sample_ray does.
#include "render/camera/camera.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <glm/geometric.hpp>

#include "scene/mitsuba/mitsuba_xml_loader.h"
#include "scene/scene_test_support.h"

namespace tessera {
namespace {

struct CameraReferenceRow {
  int sensor;
  glm::vec2 sample;  ///< film position / film size, x right, y down
  glm::dvec3 o, d;
};

#include "render/camera/mitsuba_camera_reference.inc"

Scene scene_of(const char* sensor_xml) {
  return parse_mitsuba_scene(std::string("<scene version=\"3.0.0\">") + sensor_xml + "</scene>",
                             "camera.xml", testing::memory_reader({}));
}

TEST(Camera, RaysMatchMitsubasSensors) {
  for (const CameraReferenceRow& row : kCameraRays) {
    SCOPED_TRACE("sensor " + std::to_string(row.sensor) + " at (" +
                 std::to_string(row.sample.x) + ", " + std::to_string(row.sample.y) + ")");
    const Scene scene = scene_of(kCameraXml[row.sensor]);
    const ProjectiveCamera camera(scene.camera, scene.film.width, scene.film.height);
    const glm::vec2 film = row.sample * glm::vec2(scene.film.width, scene.film.height);
    const Ray ray = camera.generate_ray(film, glm::vec2(0.5f));
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(ray.d[i], row.d[i], 2e-6) << "direction " << i;
    // Float rounding relative to the scene's extent (the Cornell-box sized view spans 600).
    const double scale = std::max(1.0, glm::length(row.o));
    if (scene.camera.projection == Projection::orthographic) {
      for (int i = 0; i < 3; ++i) EXPECT_NEAR(ray.o[i], row.o[i], 2e-6 * scale) << "origin " << i;
    } else {
      // Mitsuba starts a perspective ray at near_clip (Tessera at the pinhole, docs/mitsuba.md
      // "Clip planes"): the same line.
      const glm::dvec3 offset = row.o - glm::dvec3(ray.o);
      EXPECT_LT(glm::length(glm::cross(offset, row.d)), 2e-6 * scale);
      EXPECT_GT(glm::dot(offset, row.d), 0);
    }
  }
}

// A Mitsuba sensor rendered at another size (a job's --width / --height) frames the scene as
// the same sensor with a film of that size does, as Mitsuba frames a film of that size: a
// diagonal field of view (and focal_length, Mitsuba's default, a diagonal angle) becomes the
// horizontal one for the image's aspect, an orthographic view's height follows the aspect.
// Fixed at the scene's film's aspect instead, a default-lens view rendered 96 x 32 from a
// 64 x 48 film would come out 16 % narrower than Mitsuba's (docs/mitsuba.md).
TEST(Camera, AnotherImageSizeFramesAsAFilmOfThatSize) {
  const auto sensor = [](const std::string& lens, int width, int height) {
    return std::string("<sensor type=\"") + (lens == "ortho" ? "orthographic" : "perspective") + "\">" +
           (lens == "diagonal"  ? "<float name=\"fov\" value=\"50\"/><string name=\"fov_axis\" value=\"diagonal\"/>"
            : lens == "focal"   ? "<string name=\"focal_length\" value=\"35mm\"/>"
            : lens == "ortho"   ? "<transform name=\"to_world\"><scale x=\"2\" y=\"3\"/></transform>"
                                : "") +
           "<film type=\"hdrfilm\"><integer name=\"width\" value=\"" + std::to_string(width) +
           "\"/><integer name=\"height\" value=\"" + std::to_string(height) +
           "\"/><rfilter type=\"box\"/></film></sensor>";
  };
  for (const std::string lens : {"default", "diagonal", "focal", "ortho"}) {
    const Scene made = scene_of(sensor(lens, 64, 48).c_str());
    for (const glm::ivec2 size : {glm::ivec2(96, 32), glm::ivec2(30, 90), glm::ivec2(128, 96)}) {
      SCOPED_TRACE(lens + " at " + std::to_string(size.x) + "x" + std::to_string(size.y));
      const Scene film_of_that_size = scene_of(sensor(lens, size.x, size.y).c_str());
      const ProjectiveCamera resized(made.camera, size.x, size.y);
      const ProjectiveCamera own(film_of_that_size.camera, size.x, size.y);
      for (const glm::vec2 film : {glm::vec2(0, 0), glm::vec2(float(size.x), float(size.y)), glm::vec2(7.25f, 3.5f)}) {
        const Ray a = resized.generate_ray(film, glm::vec2(0.5f));
        const Ray b = own.generate_ray(film, glm::vec2(0.5f));
        for (int i = 0; i < 3; ++i) {
          EXPECT_NEAR(a.d[i], b.d[i], 1e-6) << "direction " << i;
          EXPECT_NEAR(a.o[i], b.o[i], 1e-6) << "origin " << i;
        }
      }
    }
  }
}

/// An orthographic camera at `position` looking down -z, up +y (image x runs along +x).
Camera orthographic_down_z(glm::dvec3 position, glm::dvec2 view_size) {
  Camera c;
  c.projection = Projection::orthographic;
  c.position = position;
  c.look_at = position - glm::dvec3(0, 0, 3);
  c.up = {0, 1, 0};
  c.view_size = view_size;
  return c;
}

TEST(Camera, OrthographicRaysAreParallelAndCoverTheView) {
  const Camera c = orthographic_down_z({1, 2, 3}, {4, 1});
  const ProjectiveCamera camera(c, 8, 2);  // the view's aspect need not be the film's
  const Ray top_left = camera.generate_ray({0, 0}, {0.3f, 0.7f});
  const Ray bottom_right = camera.generate_ray({8, 2}, {0.9f, 0.1f});
  EXPECT_EQ(top_left.d, glm::vec3(0, 0, -1));
  EXPECT_EQ(bottom_right.d, glm::vec3(0, 0, -1));
  EXPECT_NEAR(top_left.o.x, -1, 1e-6);
  EXPECT_NEAR(top_left.o.y, 2.5, 1e-6);
  EXPECT_NEAR(bottom_right.o.x, 3, 1e-6);
  EXPECT_NEAR(bottom_right.o.y, 1.5, 1e-6);
  EXPECT_NEAR(bottom_right.o.z, 3, 1e-6);
}

// A Mitsuba orthographic sensor's view (view_aspect set) keeps its width and takes its height
// from the image's aspect, as Mitsuba frames it: rendered at the film's own size, exactly
// view_size; at another aspect (`--width`/`--height`), view_size.y * view_aspect / aspect. A
// native view (view_aspect 0) stays view_size whatever the image.
TEST(Camera, OrthographicViewFollowsTheImagesAspectWhereMitsubaMadeIt) {
  Camera c = orthographic_down_z({0, 0, 3}, {4, 2.4});  // made for a 200 x 120 film: 2 x 1.2 local, scaled by 2
  c.view_aspect = 200.0 / 120.0;
  // The top left corner's ray origin.
  const auto corner = [&](int width, int height) {
    return ProjectiveCamera(c, width, height).generate_ray({0, 0}, {0.5f, 0.5f}).o;
  };
  EXPECT_EQ(corner(200, 120).y, 1.2f);  // the film's own aspect: exactly view_size
  EXPECT_EQ(corner(100, 60).y, 1.2f);
  EXPECT_FLOAT_EQ(corner(96, 58).y, float(1.2 * (200.0 / 120.0) / (96.0 / 58.0)));
  EXPECT_FLOAT_EQ(corner(100, 100).y, float(1.2 * (200.0 / 120.0)));
  EXPECT_EQ(corner(96, 58).x, -2.0f);  // the width stays
  EXPECT_EQ(corner(100, 100).x, -2.0f);
  c.view_aspect = 0;  // a native view: view_size at any image size
  EXPECT_EQ(corner(96, 58).y, 1.2f);
  EXPECT_EQ(corner(100, 100).y, 1.2f);
}

}  // namespace
}  // namespace tessera
