// The importer on whole scenes: the reference Cornell box against Mitsuba's own world-space
// geometry, dispatch by file name, and top-level refusals.
#include <gtest/gtest.h>

#include <fstream>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "scene/mitsuba/mitsuba_test_support.h"
#include "scene/mitsuba/mitsuba_transform.h"
#include "scene/native/scene_writer.h"
#include "scene/scene_loader.h"

namespace tessera {
namespace {

using testing::expect_near;
using testing::face_center;
using testing::face_normal;
using testing::kSourceDir;
using testing::line_of;
using testing::mitsuba_scene;
using testing::parse_xml;
using testing::xml_error;

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
