// The native JSON writer: parse(write(scene)) == scene, bit for bit, for awkward numbers; its
// layout, names and refusals (every field of the model: scene_writer_model_test.cpp).
#include "scene/native/scene_writer.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>

#include "scene/native/json_value.h"
#include "scene/native/scene_writer_test_support.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

using testing::expect_same_scene;
using testing::round_trip;

/// A scene with the awkward numbers and every kind of field.
Scene awkward_scene() {
  Scene s;
  s.camera.position = {-0.0, 1e-300, 5e-324};
  s.camera.look_at = {0.1, 1e150, -2.5};
  s.camera.up = {0.30000000000000004, 1, 0};
  s.camera.fov_deg = 179.99999999999997;
  s.camera.fov_axis = FovAxis::larger;
  s.camera.aperture_radius = 0.05;
  s.camera.focus_distance = 123456789012345678.0;
  s.film.width = 3;
  s.film.height = 32768;
  s.render = {1234567, 12, std::numeric_limits<uint64_t>::max()};
  Material d, m, g;
  d.name = "dif \"quoted\" \\ name\x01";
  d.reflectance.value = {0, 1, 0.1};
  d.two_sided = true;
  m.name = "mirror";
  m.type = MaterialType::mirror;
  g.name = "glass";
  g.type = MaterialType::glass;
  g.ior = 1.0 / 3.0;
  s.materials = {d, m, g};
  Shape tri;
  tri.positions = {{0, 0, 0}, {1e-7, 0, 0}, {0, 123456.789, 0}, {-1, -1, -1}};
  tri.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {1, 0, 0}};
  tri.indices = {{0, 1, 2}};
  tri.material = 0;
  tri.emission = {1e30, 0, 2.5};
  tri.two_sided_emission = true;
  Shape sphere;
  sphere.kind = Shape::Kind::sphere;
  sphere.center = {1.1, -2.2, 3.3};
  sphere.radius = 0.1;
  sphere.flip_normals = true;
  sphere.material = 2;
  Shape plain;
  plain.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  plain.indices = {{0, 1, 2}};
  plain.material = 1;
  s.shapes = {tri, sphere, plain};
  return s;
}

TEST(SceneWriter, AwkwardNumbersRoundTripExactly) {
  Scene s = awkward_scene();
  Scene back = round_trip(s);
  expect_same_scene(s, back);
  EXPECT_TRUE(std::signbit(back.camera.position.x));  // -0 stays -0
}

TEST(SceneWriter, WritingIsAFixedPoint) {
  Scene s = awkward_scene();
  std::string once = write_scene_json(s);
  EXPECT_EQ(write_scene_json(round_trip(s)), once);
}

TEST(SceneWriter, CommentAndLayout) {
  std::string json = write_scene_json(awkward_scene(), "from a.xml\nsecond line");
  EXPECT_EQ(json.substr(0, json.find('\n')), "// from a.xml\\x0asecond line");
  EXPECT_NE(json.find("\"fov_axis\": \"larger\""), std::string::npos);
  EXPECT_NE(json.find("\"seed\": 18446744073709551615"), std::string::npos);
  EXPECT_NE(json.find("\"position\": [-0.0, 1e-300, 5e-324]"), std::string::npos);
  EXPECT_NE(json.find("\"dif \\\"quoted\\\" \\\\ name\\u0001\""), std::string::npos);
}

TEST(SceneWriter, NamesAreMadeValidAndUnique) {
  Scene s = awkward_scene();
  s.materials[1].name = s.materials[0].name;
  s.materials[2].name = "";
  Scene back = round_trip(s);
  EXPECT_EQ(back.materials[1].name, s.materials[0].name + " #2");
  EXPECT_EQ(back.materials[2].name, "material");
  s.materials[2].name = "bad \xff byte";
  EXPECT_EQ(round_trip(s).materials[2].name, "bad ? byte");
}

TEST(SceneWriter, RefusesWhatJsonCannotSay) {
  Scene s = awkward_scene();
  s.materials[0].two_sided = false;  // shape 0 emits from both sides
  EXPECT_THROW(write_scene_json(s), SceneError);
  s = awkward_scene();
  s.shapes[1].radius = std::numeric_limits<double>::quiet_NaN();
  try {
    write_scene_json(s);
    ADD_FAILURE() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("shapes[1] (): nan cannot be written in JSON"),
              std::string::npos);
  }
  s = awkward_scene();
  s.shapes[2].material = 7;
  EXPECT_THROW(write_scene_json(s), SceneError);
}

}  // namespace
}  // namespace tessera
