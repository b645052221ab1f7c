// The native format's volume textures (docs/scenes.md, "Volume textures"): parsing, the checks
// of the grid file and of where the texture is used, and the writer's round trip.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "scene/volume_grid_file.h"
#include "scene/native/scene_writer.h"
#include "scene/native/native_test_support.h"
#include "scene/volume_grid_test_bytes.h"

namespace tessera {
namespace {

using testing::error_of;
using testing::parse;
using testing::scene_with_shapes;
using testing::volume_grid_bytes;

const std::string kGrid = volume_grid_bytes({2, 1, 1}, 3, {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f});

/// A scene whose one sphere's diffuse reflectance is texture "v" = `texture`, plus `material`
/// keys for that material.
std::string volume_scene(const std::string& texture, const std::string& material = "") {
  return R"({"tessera": 1, "textures": {"v": )" + texture + R"(},
    "materials": {"m": {"type": "diffuse", "reflectance": {"texture": "v"})" + material + R"(}},
    "shapes": [{"type": "sphere", "radius": 1, "material": "m"}]})";
}

TEST(VolumeTextureParse, GridFileWithItsPlacementFilterAndWrap) {
  const Scene s = parse(volume_scene(R"({"type": "volume", "file": "grids/g.vol",
      "transform": {"scale": 2, "translate": [1, 0, 0]}, "filter": "nearest", "wrap": "mirror"})"),
                        {{"grids/g.vol", kGrid}});
  ASSERT_EQ(s.textures.size(), 1u);
  const Texture& t = s.textures[0];
  EXPECT_EQ(t.kind, TextureKind::volume);
  EXPECT_EQ(t.file, "grids/g.vol");
  ASSERT_TRUE(t.grid);
  EXPECT_EQ(t.grid->resolution, glm::u32vec3(2, 1, 1));
  EXPECT_EQ(t.grid->channels, 3u);
  EXPECT_EQ(t.grid->values[4], 0.5f);
  EXPECT_EQ(t.filter, TextureFilter::nearest);
  EXPECT_EQ(t.wrap, TextureWrap::mirror);
  const glm::dmat4 expected = glm::scale(glm::translate(glm::dmat4(1.0), {1, 0, 0}), glm::dvec3(2));
  EXPECT_EQ(t.volume_to_world, expected);
  EXPECT_EQ(s.referenced_files, std::vector<std::string>{"grids/g.vol"});
  EXPECT_EQ(s.materials[0].reflectance.texture, 0);
}

TEST(VolumeTextureParse, DefaultsAreMitsubasTrilinearAndClamp) {
  const Scene s = parse(volume_scene(R"({"type": "volume", "file": "g.vol"})"), {{"g.vol", kGrid}});
  EXPECT_EQ(s.textures[0].filter, TextureFilter::bilinear);
  EXPECT_EQ(s.textures[0].wrap, TextureWrap::clamp);
  EXPECT_EQ(s.textures[0].volume_to_world, glm::dmat4(1.0));
}

TEST(VolumeTextureParse, Constants) {
  const Scene one = parse(volume_scene(R"({"type": "volume", "value": 2.5})"));
  EXPECT_EQ(one.textures[0].kind, TextureKind::volume);
  EXPECT_FALSE(one.textures[0].grid);
  EXPECT_EQ(one.textures[0].value, glm::dvec3(2.5));
  EXPECT_EQ(one.textures[0].channels, 1);
  EXPECT_TRUE(one.referenced_files.empty());
  const Scene three = parse(volume_scene(R"({"type": "volume", "value": [0.1, 0.2, 0.3]})"));
  EXPECT_EQ(three.textures[0].value, glm::dvec3(0.1, 0.2, 0.3));
  EXPECT_EQ(three.textures[0].channels, 3);
}

TEST(VolumeTextureParse, BadGridsAreRefusedNamingTheFile) {
  auto error_with = [](const std::string& bytes) {
    return error_of(volume_scene(R"({"type": "volume", "file": "g.vol"})"), {{"g.vol", bytes}});
  };
  EXPECT_EQ(error_with(volume_grid_bytes({1, 1, 1}, 2, {1, 2})),
            "textures.v.file: g.vol: has 2 channels; a volume texture reads 1 (grey) or 3 (RGB), "
            "as Mitsuba's gridvolume does for colours");
  const std::string truncated = error_with(kGrid.substr(0, kGrid.size() - 4));
  EXPECT_EQ(truncated.rfind("textures.v.file: g.vol: ", 0), 0u) << truncated;
  const std::string nan = error_with(volume_grid_bytes({1, 1, 1}, 1, {std::nanf("")}));
  EXPECT_EQ(nan.rfind("textures.v.file: g.vol: ", 0), 0u) << nan;
  const std::string missing = error_of(volume_scene(R"({"type": "volume", "file": "g.vol"})"));
  EXPECT_EQ(missing, "textures.v.file: g.vol: no such file in the scene's folder");
  EXPECT_EQ(error_of(volume_scene(R"({"type": "volume", "file": "../g.vol"})")).rfind(
                "textures.v.file", 0),
            0u);
}

TEST(VolumeTextureParse, BadKeysAndValues) {
  const std::map<std::string, std::string> files = {{"g.vol", kGrid}};
  EXPECT_EQ(error_of(volume_scene(R"({"type": "volume", "file": "g.vol", "filter": "bilinear"})"),
                     files),
            "textures.v.filter: must be \"trilinear\" or \"nearest\" (got \"bilinear\")");
  EXPECT_EQ(error_of(volume_scene(R"({"type": "volume", "file": "g.vol", "wrap": "border"})"),
                     files),
            "textures.v.wrap: must be \"repeat\", \"mirror\" or \"clamp\" (got \"border\")");
  EXPECT_NE(error_of(volume_scene(R"({"type": "volume", "file": "g.vol",
                                      "to_uv": [[1, 0, 0], [0, 1, 0]]})"),
                     files)
                .find("to_uv"),
            std::string::npos);
  EXPECT_NE(error_of(volume_scene(R"({"type": "volume", "value": 1, "file": "g.vol"})"), files)
                .find("file"),
            std::string::npos);
  EXPECT_NE(error_of(volume_scene(R"({"type": "volume", "file": "g.vol",
      "transform": {"scale": 0}})"), files).find("textures.v.transform"),
            std::string::npos);
  EXPECT_NE(error_of(volume_scene(R"({"type": "volume"})")).find("textures.v"), std::string::npos);
}

TEST(VolumeTextureParse, OnlyMaterialParametersReadIt) {
  const std::map<std::string, std::string> files = {{"g.vol", kGrid}};
  EXPECT_EQ(error_of(volume_scene(R"({"type": "volume", "file": "g.vol"})",
                                  R"(, "bump_map": "v")"),
                     files),
            "material \"m\": texture \"v\" (volume) cannot be a bump map (Mitsuba's volume "
            "texture has no gradient, eval_1_grad)");
  EXPECT_EQ(error_of(volume_scene(R"({"type": "volume", "file": "g.vol"})",
                                  R"(, "normal_map": "v")"),
                     files),
            "material \"m\": texture \"v\" (volume) cannot be a normal map (Tessera looks normal "
            "maps up by (u, v) alone; bake it into a bitmap)");
}

TEST(VolumeTextureParse, WriterRoundTripsGridsAndConstants) {
  const std::map<std::string, std::string> files = {{"g.vol", kGrid}};
  const std::string json = R"({"tessera": 1, "textures": {
      "grid": {"type": "volume", "file": "g.vol", "transform": {"rotate": {"axis": [0, 1, 1],
               "angle": 33}, "translate": [0.1, 0.2, 0.3]}, "filter": "nearest", "wrap": "repeat"},
      "plain": {"type": "volume", "file": "g.vol"},
      "grey": {"type": "volume", "value": 0.3},
      "rgb": {"type": "volume", "value": [0.1, 0.2, 0.7]}},
    "materials": {"m": {"type": "rough_conductor", "specular_reflectance": {"texture": "grid"},
                        "alpha": {"texture": "grey"}},
                  "n": {"type": "diffuse", "reflectance": {"texture": "rgb"}},
                  "o": {"type": "diffuse", "reflectance": {"texture": "plain"}}},
    "shapes": [{"type": "sphere", "radius": 1, "material": "m"},
               {"type": "sphere", "radius": 1, "material": "n"},
               {"type": "sphere", "radius": 1, "material": "o"}]})";
  const Scene a = parse(json, files);
  const std::string written = write_scene_json(a);
  const Scene b = parse(written, files);
  ASSERT_EQ(a.textures.size(), b.textures.size());
  for (size_t i = 0; i < a.textures.size(); ++i) {
    const Texture &x = a.textures[i], &y = b.textures[i];
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.kind, y.kind);
    EXPECT_EQ(x.file, y.file);
    EXPECT_EQ(x.filter, y.filter) << x.name;
    EXPECT_EQ(x.wrap, y.wrap) << x.name;
    EXPECT_EQ(x.volume_to_world, y.volume_to_world) << x.name;  // bit for bit
    EXPECT_EQ(x.value, y.value) << x.name;
    EXPECT_EQ(x.channels, y.channels) << x.name;
    ASSERT_EQ(bool(x.grid), bool(y.grid)) << x.name;
    if (x.grid) {
      EXPECT_EQ(x.grid->values, y.grid->values);
    }
  }
  EXPECT_EQ(b.referenced_files, std::vector<std::string>{"g.vol"});
  EXPECT_EQ(write_scene_json(b), written);
  EXPECT_NE(written.find(R"("plain": {"type": "volume", "file": "g.vol", "filter": "trilinear", )"
                         R"("wrap": "clamp"})"),
            std::string::npos)
      << written;
}

}  // namespace
}  // namespace tessera
