// Whole scene files read from disk through the loader: the reference Cornell box against
// Mitsuba's own world-space geometry and camera, dispatch by file name, -D parameters, and the
// native writer's round trip of the scenes in scenes/.
#include "scene/loader/scene_loader.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "scene/mitsuba/mitsuba_sensor_test_support.h"
#include "scene/mitsuba/mitsuba_test_support.h"
#include "scene/mitsuba/mitsuba_xml_loader.h"
#include "scene/native/scene_writer_test_support.h"

namespace tessera {
namespace {

using testing::expect_near;
using testing::expect_same_scene;
using testing::face_center;
using testing::face_normal;
using testing::image_right;
using testing::kSourceDir;
using testing::mitsuba_scene;
using testing::parse_xml;
using testing::round_trip;
using testing::sampler_scene;

const std::string kCbox = kSourceDir + "/tests/data/reference/cbox/";

nlohmann::json resolved() {
  std::ifstream in(kCbox + "resolved.json");
  return nlohmann::json::parse(in);
}

glm::dvec3 vec(const nlohmann::json& j) {
  return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

const Shape& shape_with_id(const Scene& s, const std::string& id) {
  for (const Shape& shape : s.shapes) {
    if (shape.origin.find("id=\"" + id + "\"") != std::string::npos) return shape;
  }
  throw std::runtime_error("no shape " + id);
}

TEST(MitsubaScene, ReferenceCornellBoxLoads) {
  Scene s = load_scene_file(kCbox + "mitsuba.xml");
  EXPECT_EQ(s.film.width, 256);
  EXPECT_EQ(s.film.height, 256);
  EXPECT_EQ(s.render.spp, 64);       // $spp's default
  EXPECT_EQ(s.render.max_depth, 8);  // $max_depth's default
  EXPECT_EQ(s.render.seed, 0u);
  ASSERT_EQ(s.shapes.size(), 8u);
  size_t triangles = 0;
  for (const Shape& shape : s.shapes) triangles += shape.indices.size();
  EXPECT_EQ(triangles, 5 * 2 + 2 + 2 * 12u);
  ASSERT_EQ(s.materials.size(), 3u);
  EXPECT_EQ(s.materials[0].name, "white");
  EXPECT_EQ(s.materials[0].reflectance.value, glm::dvec3(0.885809, 0.698859, 0.666422));
  const Shape& light = shape_with_id(s, "light");
  EXPECT_EQ(light.emission, glm::dvec3(18.387, 13.9873, 6.75357));
  EXPECT_EQ(s.materials[light.material].name, "white");
  EXPECT_TRUE(s.referenced_files.empty());
}

TEST(MitsubaScene, ReferenceCornellBoxMatchesMitsubasWorldSpaceGeometry) {
  Scene s = load_scene_file(kCbox + "mitsuba.xml");
  nlohmann::json r = resolved();
  for (const nlohmann::json& quad : r["quads"]) {
    std::string name = quad["name"];
    std::string id = name.substr(
        0, name.find("-box") == std::string::npos ? name.size() : name.find("-box") + 4);
    const Shape& shape = shape_with_id(s, id);
    glm::dvec3 center(0);
    for (const nlohmann::json& v : quad["vertices"]) {
      glm::dvec3 p = vec(v);
      center += p / 4.0;
      double nearest = 1e9;
      for (const glm::dvec3& q : shape.positions) nearest = std::min(nearest, glm::length(p - q));
      EXPECT_LT(nearest, 1e-6) << name;
    }
    // The face over this quad's centre faces the way Mitsuba's does.
    bool found = false;
    for (size_t t = 0; t < shape.indices.size(); ++t) {
      glm::dvec3 n = face_normal(shape, t);
      if (glm::dot(n, vec(quad["normal"])) > 1 - 1e-6 &&
          std::abs(glm::dot(face_center(shape, t) - center, n)) < 1e-6) {
        found = true;
      }
    }
    EXPECT_TRUE(found) << name;
  }
}

TEST(MitsubaScene, TransformOperationsComposeAsMitsubasMatrices) {
  // resolved.json gives each box as T * Ry * S; mitsuba.xml writes the product Mitsuba
  // computed. Written as operations in document order (scale, rotate, translate), they agree.
  nlohmann::json boxes = resolved()["boxes"];
  Scene s = load_scene_file(kCbox + "mitsuba.xml");
  for (const std::string id : {"large-box", "small-box"}) {
    const nlohmann::json& b = boxes[id];
    char ops[512];
    std::snprintf(ops, sizeof ops,
                  "<shape type=\"cube\" id=\"%s\"><transform name=\"to_world\">"
                  "<scale x=\"%.17g\" y=\"%.17g\" z=\"%.17g\"/><rotate y=\"1\" angle=\"%.17g\"/>"
                  "<translate x=\"%.17g\" y=\"%.17g\" z=\"%.17g\"/></transform></shape>",
                  id.c_str(), b["scale"][0].get<double>(), b["scale"][1].get<double>(),
                  b["scale"][2].get<double>(), b["rotate_y_deg"].get<double>(),
                  b["translate"][0].get<double>(), b["translate"][1].get<double>(),
                  b["translate"][2].get<double>());
    Scene mine = parse_xml(mitsuba_scene(ops));
    const Shape& want = shape_with_id(s, id);
    const Shape& got = mine.shapes.at(0);
    ASSERT_EQ(got.positions.size(), want.positions.size());
    for (size_t i = 0; i < got.positions.size(); ++i) {
      expect_near(got.positions[i], want.positions[i], 1e-7);  // the XML's floats: 1e-7
    }
  }
}

TEST(MitsubaScene, LoadSceneFileAndParseSceneAnyChooseByExtension) {
  std::string xml = mitsuba_scene("<shape type=\"cube\"/>");
  FileReader none = testing::memory_reader({});
  EXPECT_EQ(parse_scene_any("scene.XML", xml, none).shapes.size(), 1u);
  EXPECT_EQ(parse_scene_any("scene.xml", xml, none).shapes.size(), 1u);
  // Not XML by name: read as JSON, which this is not.
  try {
    parse_scene_any("scene.json", xml, none);
    ADD_FAILURE() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("scene.json: line 1, column 1"), std::string::npos);
  }
  std::string json = R"({"tessera": 1})";
  EXPECT_EQ(parse_scene_any("s.json", json, none).shapes.size(), 0u);
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

TEST(MitsubaParameters, LoadSceneBundleAppliesThemAndKeepsTheText) {
  namespace fs = std::filesystem;
  const fs::path folder = fs::temp_directory_path() / ("tessera_define_" + std::to_string(::getpid()));
  fs::create_directories(folder);
  const std::string xml = sampler_scene("");
  std::ofstream(folder / "scene.xml") << xml;
  std::ofstream(folder / "scene.json") << "{}";
  const SceneOnDisk loaded = load_scene_bundle(folder / "scene.xml", std::nullopt, {{"depth", "2"}});
  EXPECT_EQ(loaded.scene.render.max_depth, 2);
  EXPECT_EQ(loaded.scene_text, with_mitsuba_parameters(xml, "scene.xml", {{"depth", "2"}}));
  EXPECT_EQ(load_scene_bundle(folder / "scene.xml", std::nullopt, {{"depth", "2"}}).scene_text,
            loaded.scene_text);
  try {
    load_scene_file(folder / "scene.json", std::nullopt, {{"depth", "2"}});
    FAIL() << "-D on a native scene was accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("-D sets parameters of Mitsuba 3 XML scenes"),
              std::string::npos)
        << e.what();
  }
  fs::remove_all(folder);
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

}  // namespace
}  // namespace tessera
