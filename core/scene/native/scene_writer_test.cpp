// The native JSON writer: parse(write(scene)) == scene, bit for bit.
#include "scene/native/scene_writer.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>

#include "scene/native/json_value.h"
#include "scene/scene_error.h"
#include "scene/mitsuba/mitsuba_test_support.h"

namespace tessera {
namespace {

using testing::kSourceDir;
using testing::memory_reader;

bool same_bits(double a, double b) {
  return std::bit_cast<uint64_t>(a) == std::bit_cast<uint64_t>(b);
}

::testing::AssertionResult same_bits(const glm::dvec3& a, const glm::dvec3& b) {
  for (int i = 0; i < 3; ++i) {
    if (!same_bits(a[i], b[i])) {
      return ::testing::AssertionFailure()
             << "component " << i << ": " << format_number(a[i]) << " vs " << format_number(b[i]);
    }
  }
  return ::testing::AssertionSuccess();
}

/// Every field the renderer reads, compared bit for bit. Not compared: Shape::origin,
/// dropped_triangles and referenced_files (the JSON keeps no such thing) and flip_normals of
/// triangle shapes (applied to their winding).
void expect_same_scene(const Scene& a, const Scene& b) {
  EXPECT_TRUE(same_bits(a.camera.position, b.camera.position));
  EXPECT_TRUE(same_bits(a.camera.look_at, b.camera.look_at));
  EXPECT_TRUE(same_bits(a.camera.up, b.camera.up));
  EXPECT_TRUE(same_bits(a.camera.fov_deg, b.camera.fov_deg));
  EXPECT_EQ(a.camera.fov_axis, b.camera.fov_axis);
  EXPECT_TRUE(same_bits(a.camera.aperture_radius, b.camera.aperture_radius));
  EXPECT_TRUE(same_bits(a.camera.focus_distance, b.camera.focus_distance));
  EXPECT_EQ(a.film.width, b.film.width);
  EXPECT_EQ(a.film.height, b.film.height);
  EXPECT_EQ(a.render.spp, b.render.spp);
  EXPECT_EQ(a.render.max_depth, b.render.max_depth);
  EXPECT_EQ(a.render.seed, b.render.seed);
  ASSERT_EQ(a.materials.size(), b.materials.size());
  for (size_t i = 0; i < a.materials.size(); ++i) {
    const Material &x = a.materials[i], &y = b.materials[i];
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.type, y.type);
    EXPECT_TRUE(same_bits(x.reflectance.value, y.reflectance.value));
    EXPECT_TRUE(same_bits(x.ior, y.ior));
    EXPECT_EQ(x.two_sided, y.two_sided);
  }
  ASSERT_EQ(a.shapes.size(), b.shapes.size());
  for (size_t i = 0; i < a.shapes.size(); ++i) {
    const Shape &x = a.shapes[i], &y = b.shapes[i];
    SCOPED_TRACE(x.origin);
    ASSERT_EQ(x.kind, y.kind);
    EXPECT_EQ(x.material, y.material);
    EXPECT_TRUE(same_bits(x.emission, y.emission));
    EXPECT_EQ(x.two_sided_emission, y.two_sided_emission);
    if (x.kind == Shape::Kind::sphere) {
      EXPECT_TRUE(same_bits(x.center, y.center));
      EXPECT_TRUE(same_bits(x.radius, y.radius));
      EXPECT_EQ(x.flip_normals, y.flip_normals);
      continue;
    }
    ASSERT_EQ(x.positions.size(), y.positions.size());
    for (size_t k = 0; k < x.positions.size(); ++k) {
      ASSERT_TRUE(same_bits(x.positions[k], y.positions[k])) << "vertex " << k;
    }
    ASSERT_EQ(x.normals.size(), y.normals.size());
    for (size_t k = 0; k < x.normals.size(); ++k) {
      ASSERT_TRUE(same_bits(x.normals[k], y.normals[k])) << "normal " << k;
    }
    EXPECT_EQ(x.indices, y.indices);
  }
}

Scene round_trip(const Scene& scene) {
  return parse_scene(write_scene_json(scene), memory_reader({}));
}

TEST(SceneWriter, MitsubaReferenceSceneRoundTripsExactly) {
  Scene s = load_scene_file(kSourceDir + "/tests/data/reference/cbox/mitsuba.xml");
  expect_same_scene(s, round_trip(s));
}

TEST(SceneWriter, MitsubaMeshesWithNormalsRoundTripExactly) {
  // The bunny gets Mitsuba's computed normals, the McGuire spheres the file's: both stored in
  // the form the parser's renormalisation leaves alone.
  FileReader scenes = folder_reader(kSourceDir + "/scenes");
  Scene s = parse_mitsuba_scene(testing::mitsuba_scene(R"(
      <shape type="ply"><string name="filename" value="meshes/bunny_lowres.ply"/>
        <transform name="to_world"><scale value="7"/><rotate y="1" angle="30"/></transform></shape>
      <shape type="obj"><string name="filename" value="mcguire-cornell/CornellBox-Sphere.obj"/>
        <bsdf type="twosided"><bsdf type="diffuse"/></bsdf></shape>)"),
                                "meshes.xml", scenes);
  ASSERT_FALSE(s.shapes.at(0).normals.empty());
  ASSERT_FALSE(s.shapes.at(1).normals.empty());
  expect_same_scene(s, round_trip(s));
}

TEST(SceneWriter, NativeScenesWithoutNormalsRoundTripExactly) {
  for (const char* file : {"cornell.json", "hexroom.json"}) {
    SCOPED_TRACE(file);
    Scene s = load_scene_file(kSourceDir + "/scenes/" + file);
    expect_same_scene(s, round_trip(s));
  }
}

TEST(SceneWriter, NativeScenesWithFileNormalsComeBackWithinAnUlp) {
  // The parser renormalises normals it reads: a normal normalisation moves comes back moved.
  Scene s = load_scene_file(kSourceDir + "/scenes/cornell-sphere.json");
  Scene back = round_trip(s);
  ASSERT_EQ(back.shapes.size(), s.shapes.size());
  for (size_t i = 0; i < s.shapes.size(); ++i) {
    ASSERT_EQ(back.shapes[i].normals.size(), s.shapes[i].normals.size());
    for (size_t k = 0; k < s.shapes[i].normals.size(); ++k) {
      EXPECT_LE(glm::length(back.shapes[i].normals[k] - s.shapes[i].normals[k]), 1e-15);
    }
    EXPECT_EQ(back.shapes[i].positions, s.shapes[i].positions);
  }
}

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

TEST(SceneWriter, AnEmptySceneIsValid) {
  Scene s;
  expect_same_scene(s, round_trip(s));
}

// Before, a material native JSON cannot express was written as "{}" and read back as diffuse.
TEST(SceneWriter, AMaterialNativeJsonCannotExpressIsRefusedByName) {
  Scene s;
  Material plastic;
  plastic.name = "shiny";
  plastic.type = MaterialType::plastic;
  s.materials.push_back(plastic);
  try {
    write_scene_json(s);
    FAIL() << "written";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("materials.shiny: this material type cannot be written"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace tessera
