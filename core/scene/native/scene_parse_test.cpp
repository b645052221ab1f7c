// Scene format v1: the top level, camera, film, render and materials.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <numbers>

#include "scene/native/native_test_support.h"

namespace tessera {
namespace {

using testing::error_of;
using testing::parse;
using testing::scene_with_shapes;

TEST(SceneParse, MinimalSceneHasDocumentedDefaults) {
  Scene scene = parse(R"({"tessera": 1})");
  EXPECT_EQ(scene.film.width, 256);
  EXPECT_EQ(scene.film.height, 256);
  EXPECT_EQ(scene.render.spp, 64);
  EXPECT_EQ(scene.render.max_depth, -1);
  EXPECT_EQ(scene.render.rr_depth, 3);
  EXPECT_EQ(scene.render.seed, 0u);
  EXPECT_EQ(scene.camera.fov_axis, FovAxis::x);
  EXPECT_EQ(scene.camera.aperture_radius, 0);
  EXPECT_EQ(scene.camera.focus_distance, 1);
  EXPECT_TRUE(scene.shapes.empty());
  EXPECT_TRUE(scene.materials.empty());
  EXPECT_TRUE(scene.referenced_files.empty());
}

TEST(SceneParse, DesignDocumentExampleParses) {
  // The format's example, with its comments (comments are allowed).
  Scene scene = parse(R"({
    "tessera": 1,
    "camera": { "position": [0,0,3.9], "look_at": [0,0,0], "up": [0,1,0],
                "fov": 39.3, "fov_axis": "y",          // full angle, degrees
                "aperture_radius": 0, "focus_distance": 1 },
    "film":   { "width": 320, "height": 240 },
    "render": { "spp": 128, "max_depth": 8, "seed": 7 },
    "materials": {
      "white": { "type": "diffuse", "reflectance": [0.8,0.8,0.8] },
      "mirror": { "type": "mirror" },
      "glass":  { "type": "glass", "ior": 1.5 }
    },
    "shapes": [
      { "type": "quad", "vertices": [[-1,-1,0],[1,-1,0],[1,1,0],[-1,1,0]], "material": "white" },
      { "type": "sphere", "center": [0,0,0.5], "radius": 0.3, "material": "glass" },
      { "type": "quad", "vertices": [[-0.2,0.9,-0.2],[0.2,0.9,-0.2],[0.2,0.9,0.2],[-0.2,0.9,0.2]],
        "material": "white", "emission": [17,12,4] }
    ]
  })");
  EXPECT_EQ(scene.camera.position, glm::dvec3(0, 0, 3.9));
  EXPECT_EQ(scene.camera.fov_deg, 39.3);
  EXPECT_EQ(scene.camera.fov_axis, FovAxis::y);
  EXPECT_EQ(scene.film.width, 320);
  EXPECT_EQ(scene.film.height, 240);
  EXPECT_EQ(scene.render.spp, 128);
  EXPECT_EQ(scene.render.max_depth, 8);
  EXPECT_EQ(scene.render.seed, 7u);
  ASSERT_EQ(scene.materials.size(), 3u);
  EXPECT_EQ(scene.materials[0].name, "white");  // file order
  EXPECT_EQ(scene.materials[1].name, "mirror");
  EXPECT_EQ(scene.materials[2].name, "glass");
  ASSERT_EQ(scene.shapes.size(), 3u);
  EXPECT_EQ(scene.shapes[1].kind, Shape::Kind::sphere);
  EXPECT_EQ(scene.shapes[1].material, 2u);
  EXPECT_EQ(scene.shapes[2].emission, glm::dvec3(17, 12, 4));
  EXPECT_TRUE(scene.shapes[2].is_emitter());
  EXPECT_FALSE(scene.shapes[2].two_sided_emission);
  EXPECT_EQ(scene.shapes[0].origin, "shapes[0]");
}

TEST(SceneParse, DocumentationExampleParses) {
  // docs/scenes.md's complete example (its first json block), as if saved in scenes/.
  std::ifstream doc(TESSERA_SOURCE_DIR "/docs/scenes.md");
  std::string text((std::istreambuf_iterator<char>(doc)), std::istreambuf_iterator<char>());
  size_t start = text.find("```json\n");
  ASSERT_NE(start, std::string::npos);
  start += 8;
  std::string json = text.substr(start, text.find("```", start) - start);
  Scene scene = parse_scene(json, folder_reader(TESSERA_SOURCE_DIR "/scenes"));
  ASSERT_EQ(scene.shapes.size(), 9u);
  for (size_t wall = 0; wall < 5; ++wall) {  // the room faces inward
    const Shape& quad = scene.shapes[wall];
    glm::dvec3 to_center = glm::dvec3(0, 1, 0) - testing::face_center(quad, 0);
    EXPECT_GT(glm::dot(testing::face_normal(quad, 0), to_center), 0) << wall;
  }
  const Shape& light = scene.shapes[5];
  EXPECT_NEAR(light.emission.x, 40 / (std::numbers::pi * 0.25), 1e-9);
  EXPECT_EQ(scene.materials[light.material].name, "(black)");
  EXPECT_EQ(scene.shapes[8].indices.size(), 69451u);
  EXPECT_EQ(scene.referenced_files, std::vector<std::string>{"meshes/bunny.ply"});
}

TEST(SceneParse, FovAxisValues) {
  auto axis = [](const std::string& name) {
    return parse(R"({"tessera": 1, "camera": {"fov_axis": ")" + name + R"("}})").camera.fov_axis;
  };
  EXPECT_EQ(axis("x"), FovAxis::x);
  EXPECT_EQ(axis("y"), FovAxis::y);
  EXPECT_EQ(axis("smaller"), FovAxis::smaller);
  EXPECT_EQ(axis("larger"), FovAxis::larger);
  EXPECT_EQ(axis("diagonal"), FovAxis::diagonal);
  EXPECT_EQ(error_of(R"({"tessera": 1, "camera": {"fov_axis": "diag"}})"),
            "camera.fov_axis: must be \"x\", \"y\", \"smaller\", \"larger\" or \"diagonal\" (got \"diag\")");
}

TEST(SceneParse, CameraConstraints) {
  EXPECT_EQ(error_of(R"({"tessera": 1, "camera": {"fov": 180}})"),
            "camera.fov: must be in (0, 180) degrees (got 180)");
  EXPECT_EQ(error_of(R"({"tessera": 1, "camera": {"fov": 0}})"),
            "camera.fov: must be in (0, 180) degrees (got 0)");
  EXPECT_EQ(error_of(R"({"tessera": 1, "camera": {"position": [1,2,3], "look_at": [1,2,3]}})"),
            "camera.look_at: must differ from camera.position");
  EXPECT_EQ(error_of(R"({"tessera": 1, "camera": {"position": [0,5,0], "look_at": [0,0,0]}})"),
            "camera.up: must not be parallel to the view direction");
  EXPECT_EQ(error_of(R"({"tessera": 1, "camera": {"up": [0,0,0]}})"),
            "camera.up: must be a non-zero vector");
  EXPECT_EQ(error_of(R"({"tessera": 1, "camera": {"aperture_radius": -0.1}})"),
            "camera.aperture_radius: must be >= 0 (got -0.1)");
  EXPECT_EQ(error_of(R"({"tessera": 1, "camera": {"focus_distance": 0}})"),
            "camera.focus_distance: must be > 0 (got 0)");
  Scene thin_lens =
      parse(R"({"tessera": 1, "camera": {"aperture_radius": 0.05, "focus_distance": 3}})");
  EXPECT_EQ(thin_lens.camera.aperture_radius, 0.05);
  EXPECT_EQ(thin_lens.camera.focus_distance, 3);
}

TEST(SceneParse, FilmAndRenderConstraints) {
  EXPECT_EQ(error_of(R"({"tessera": 1, "film": {"width": 0}})"),
            "film.width: must be in [1, 32768] (got 0)");
  EXPECT_EQ(error_of(R"({"tessera": 1, "film": {"height": 32769}})"),
            "film.height: must be in [1, 32768] (got 32769)");
  EXPECT_EQ(error_of(R"({"tessera": 1, "film": {"width": 12.5}})"),
            "film.width: must be an integer (got 12.5)");
  EXPECT_EQ(parse(R"({"tessera": 1, "film": {"width": 64.0}})").film.width, 64);
  EXPECT_EQ(error_of(R"({"tessera": 1, "render": {"max_depth": 0}})"),
            "render.max_depth: must be -1 (unbounded) or >= 1 (got 0)");
  EXPECT_EQ(error_of(R"({"tessera": 1, "render": {"max_depth": -2}})"),
            "render.max_depth: must be -1 (unbounded) or >= 1 (got -2)");
  EXPECT_EQ(error_of(R"({"tessera": 1, "render": {"seed": -1}})"),
            "render.seed: must be >= 0 (got -1)");
  EXPECT_EQ(parse(R"({"tessera": 1, "render": {"seed": 18446744073709551615}})").render.seed,
            18446744073709551615u);
  EXPECT_EQ(parse(R"({"tessera": 1, "render": {"max_depth": 1}})").render.max_depth, 1);
}

TEST(SceneParse, RrDepthSaysWhereRussianRouletteStarts) {
  EXPECT_EQ(parse(R"({"tessera": 1, "render": {"rr_depth": 1}})").render.rr_depth, 1);
  EXPECT_EQ(parse(R"({"tessera": 1, "render": {"rr_depth": 1000}})").render.rr_depth, 1000);
  EXPECT_EQ(error_of(R"({"tessera": 1, "render": {"rr_depth": 0}})"),
            "render.rr_depth: must be in [1, 2147483647] (got 0)");
  EXPECT_EQ(error_of(R"({"tessera": 1, "render": {"rr_depth": 2.5}})"),
            "render.rr_depth: must be an integer (got 2.5)");
}

TEST(SceneParse, FormatVersion) {
  EXPECT_EQ(error_of(R"({"camera": {}})"), "tessera: required");
  EXPECT_EQ(error_of(R"({"tessera": 2})"),
            "tessera: unsupported format version 2 (this build reads 1)");
  EXPECT_EQ(error_of(R"({"tessera": "1"})"), "tessera: must be the format version, 1");
  EXPECT_EQ(error_of(R"([1, 2])"), "scene: a scene must be a JSON object ({\"tessera\": 1, ...})");
}

TEST(SceneParse, MaterialTypesAndDefaults) {
  Scene scene = parse(R"({"tessera": 1, "materials": {
      "grey": {},
      "red": {"type": "diffuse", "reflectance": [0.9, 0.1, 0], "two_sided": true},
      "mirror": {"type": "mirror", "two_sided": true},
      "glass": {"type": "glass"},
      "air": {"type": "glass", "ior": 1.0}}})");
  ASSERT_EQ(scene.materials.size(), 5u);
  EXPECT_EQ(scene.materials[0].type, MaterialType::diffuse);
  EXPECT_EQ(scene.materials[0].reflectance.value, glm::dvec3(0.5));
  EXPECT_FALSE(scene.materials[0].two_sided);
  EXPECT_EQ(scene.materials[1].reflectance.value, glm::dvec3(0.9, 0.1, 0));
  EXPECT_TRUE(scene.materials[1].two_sided);
  EXPECT_EQ(scene.materials[2].type, MaterialType::mirror);
  EXPECT_TRUE(scene.materials[2].two_sided);
  EXPECT_EQ(scene.materials[3].type, MaterialType::glass);
  EXPECT_EQ(scene.materials[3].ior, 1.5);
  EXPECT_EQ(scene.materials[4].ior, 1.0);
}

TEST(SceneParse, MaterialKeysBelongToTheirType) {
  EXPECT_EQ(error_of(R"({"tessera": 1, "materials": {"m": {"type": "diffuse", "ior": 1.3}}})"),
            "materials.m.ior: only glass kinds, plastics, principled materials and hair have an ior");
  EXPECT_EQ(
      error_of(R"({"tessera": 1, "materials": {"m": {"type": "mirror", "reflectance": [1,1,1]}}})"),
      "materials.m.reflectance: only diffuse materials have a reflectance");
  EXPECT_EQ(error_of(R"({"tessera": 1, "materials": {"g": {"type": "glass", "two_sided": true}}})"),
            "materials.g.two_sided: glass is always two-sided (remove this key)");
  EXPECT_EQ(error_of(R"({"tessera": 1, "materials": {"g": {"type": "glass", "ior": 0}}})"),
            "materials.g.ior: must be > 0 (got 0)");
  EXPECT_EQ(error_of(R"({"tessera": 1, "materials": {"m": {"type": "velvet"}}})"),
            "materials.m.type: unknown material type \"velvet\" (expected diffuse, mirror, glass, "
            "conductor, rough_conductor, rough_glass, thin_glass, plastic, rough_plastic, "
            "pplastic, principled, principled_thin, polarizer, hair or blend)");
  EXPECT_EQ(error_of(R"({"tessera": 1, "materials": {"white": {"reflectance": [0.5, 1.2, 0.5]}}})"),
            "materials.white.reflectance[1]: must be in [0, 1] (got 1.2)");
  EXPECT_EQ(error_of(R"({"tessera": 1, "materials": {"m": {"roughness": 0.1}}})"),
            "materials.m.roughness: unknown key (a diffuse material has: type, reflectance, "
            "two_sided, opacity, normal_map, bump_map, bump_scale, back)");
}

TEST(SceneParse, TwoSidedShapeGetsOneTwoSidedCopyPerMaterial) {
  Scene scene = parse(scene_with_shapes(R"(
      {"type": "sphere", "material": "white", "two_sided": true},
      {"type": "sphere", "material": "white", "two_sided": true},
      {"type": "sphere", "material": "white"},
      {"type": "sphere", "material": "glass", "two_sided": true})"));
  ASSERT_EQ(scene.materials.size(), 4u);  // white, mirror, glass, "white (two-sided)"
  const Material& copy = scene.materials[3];
  EXPECT_EQ(copy.name, "white (two-sided)");
  EXPECT_TRUE(copy.two_sided);
  EXPECT_EQ(copy.reflectance.value, glm::dvec3(0.8));
  EXPECT_EQ(scene.shapes[0].material, 3u);
  EXPECT_EQ(scene.shapes[1].material, 3u);
  EXPECT_EQ(scene.shapes[2].material, 0u);
  EXPECT_EQ(scene.shapes[3].material, 2u);           // glass is two-sided already
  EXPECT_FALSE(scene.shapes[0].two_sided_emission);  // not a light
}

TEST(SceneParse, EmitterWithoutMaterialIsBlack) {
  Scene scene = parse(scene_with_shapes(R"({"type": "sphere", "emission": [1, 2, 3]})"));
  ASSERT_EQ(scene.shapes.size(), 1u);
  const Material& black = scene.materials[scene.shapes[0].material];
  EXPECT_EQ(black.name, "(black)");
  EXPECT_EQ(black.type, MaterialType::diffuse);
  EXPECT_EQ(black.reflectance.value, glm::dvec3(0));
  EXPECT_EQ(error_of(scene_with_shapes(R"({"type": "sphere"})")),
            "shapes[0].material: required (only lights may omit it)");
}

TEST(SceneParse, EmitterMayUseAnyMaterial) {
  Scene scene =
      parse(scene_with_shapes(R"({"type": "sphere", "material": "glass", "emission": [1, 1, 1]},
                                           {"type": "sphere", "material": "mirror", "power": 10})"));
  EXPECT_TRUE(scene.shapes[0].is_emitter());
  EXPECT_TRUE(scene.shapes[1].is_emitter());
}

}  // namespace
}  // namespace tessera
