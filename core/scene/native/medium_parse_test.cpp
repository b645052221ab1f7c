// The "media" of native scenes: parsing, errors that name the field, and the writer's round trip.
#include <gtest/gtest.h>

#include <bit>

#include "scene/native/scene_writer.h"
#include "scene/native/native_test_support.h"
#include "scene/volume_grid_test_bytes.h"

namespace tessera {
namespace {

using testing::error_of;
using testing::parse;

const char* kFog = R"("media": {
    "fog": {"type": "homogeneous", "sigma_t": [1, 2, 3], "albedo": [0.9, 0.5, 0.1], "scale": 2.5,
            "phase": {"type": "hg", "g": -0.3}, "sample_emitters": false},
    "air": {}},
  "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "medium": "air"}, )";

std::string fog_scene(const std::string& shape_keys = R"("interior": "fog", "exterior": "air")") {
  return testing::scene_with_shapes(
      R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "glass", )" + shape_keys + "}",
      kFog);
}

TEST(NativeMedia, ParsesEveryKeyAndMitsubasDefaults) {
  Scene s = parse(fog_scene());
  ASSERT_EQ(s.media.size(), 2u);
  const Medium& fog = s.media[0];
  EXPECT_EQ(fog.name, "fog");
  EXPECT_EQ(fog.kind, MediumKind::homogeneous);
  EXPECT_EQ(fog.sigma_t.value, glm::dvec3(1, 2, 3));
  EXPECT_EQ(fog.albedo.value, glm::dvec3(0.9, 0.5, 0.1));
  EXPECT_EQ(fog.scale, 2.5);
  EXPECT_EQ(fog.phase, PhaseKind::hg);
  EXPECT_EQ(fog.g, -0.3);
  EXPECT_FALSE(fog.sample_emitters);
  const Medium& air = s.media[1];  // Mitsuba's homogeneous defaults
  EXPECT_EQ(air.sigma_t.value, glm::dvec3(1));
  EXPECT_EQ(air.albedo.value, glm::dvec3(0.75));
  EXPECT_EQ(air.phase, PhaseKind::isotropic);
  EXPECT_TRUE(air.sample_emitters);
  EXPECT_EQ(s.shapes[0].interior, 0);
  EXPECT_EQ(s.shapes[0].exterior, 1);
  EXPECT_EQ(s.camera.medium, 1);
  EXPECT_EQ(parse(fog_scene(R"("interior": "fog")")).shapes[0].exterior, -1);
  // hg's default g is Mitsuba's 0.8.
  Scene hg = parse(R"({"tessera": 1, "media": {"m": {"phase": {"type": "hg"}}}})");
  EXPECT_EQ(hg.media[0].g, 0.8);
}

TEST(NativeMedia, ErrorsNameTheField) {
  auto with = [](const std::string& medium) {
    return error_of(R"({"tessera": 1, "media": {"m": )" + medium + "}}");
  };
  EXPECT_NE(with(R"({"sigma_t": [1, -1, 1]})").find("media.m.sigma_t[1]: must be >= 0"), std::string::npos)
      << with(R"({"sigma_t": [1, -1, 1]})");
  EXPECT_NE(with(R"({"albedo": [0.5, 1.5, 0]})").find("media.m.albedo[1]"), std::string::npos)
      << with(R"({"albedo": [0.5, 1.5, 0]})");
  EXPECT_NE(with(R"({"phase": {"type": "hg", "g": 1}})").find("media.m.phase.g: must be in (-1, 1)"),
            std::string::npos) << with(R"({"phase": {"type": "hg", "g": 1}})");
  EXPECT_NE(with(R"({"phase": {"type": "hg", "g": -1.5}})").find("media.m.phase.g"), std::string::npos);
  EXPECT_NE(with(R"({"phase": {"type": "rayleigh"}})").find("unknown phase function \"rayleigh\""),
            std::string::npos);
  EXPECT_NE(with(R"({"phase": {"type": "isotropic", "g": 0.5}})").find("media.m.phase.g"), std::string::npos);
  EXPECT_NE(with(R"({"scale": -2})").find("media.m.scale: must be >= 0"), std::string::npos);
  EXPECT_NE(with(R"({"type": "fog"})").find("media.m.type: unknown medium type \"fog\""), std::string::npos);
  EXPECT_NE(with(R"({"density": 1})").find("media.m.density"), std::string::npos);
  EXPECT_NE(with(R"({"sigma_t": {"texture": "t"}})").find("media.m.sigma_t"), std::string::npos);
  const std::string homogeneous_grid = error_of(R"({"tessera": 1, "textures": {"d": {"type": "volume", "value": 2}},
      "media": {"m": {"sigma_t": {"texture": "d"}}}})");
  EXPECT_NE(homogeneous_grid.find("media.m.sigma_t: a homogeneous medium's sigma_t is a constant"), std::string::npos)
      << homogeneous_grid;
  EXPECT_NE(error_of(fog_scene(R"("interior": "smoke")")).find("shapes[0].interior: unknown medium \"smoke\""),
            std::string::npos)
      << error_of(fog_scene(R"("interior": "smoke")"));
  EXPECT_NE(error_of(R"({"tessera": 1, "camera": {"medium": "smoke"}})").find("camera.medium: unknown medium"),
            std::string::npos);
}

TEST(NativeMedia, HeterogeneousReadsVolumeTexturesOnly) {
  const std::string grid = testing::volume_grid_bytes({2, 2, 2}, 1, {0, 1, 2, 3, 4, 5, 6, 7});
  Scene s = parse(R"({"tessera": 1, "textures": {"density": {"type": "volume", "file": "d.vol"},
      "checks": {"type": "checkerboard"}},
      "media": {"smoke": {"type": "heterogeneous", "sigma_t": {"texture": "density", "scale": 3}}}})",
                  {{"d.vol", grid}});
  EXPECT_EQ(s.media[0].kind, MediumKind::heterogeneous);
  EXPECT_EQ(s.media[0].sigma_t.texture, 0);
  EXPECT_EQ(s.media[0].sigma_t.value, glm::dvec3(3));
  const std::string checks = error_of(R"({"tessera": 1, "textures": {"checks": {"type": "checkerboard"}},
      "media": {"smoke": {"type": "heterogeneous", "sigma_t": {"texture": "checks"}}}})");
  EXPECT_NE(checks.find("media.smoke.sigma_t.texture: a medium reads volume textures only"), std::string::npos)
      << checks;
}

TEST(NativeMedia, RoundTripThroughTheWriter) {
  Scene s = parse(fog_scene());
  const std::string json = write_scene_json(s);
  Scene back = parse(json);
  ASSERT_EQ(back.media.size(), s.media.size());
  for (size_t i = 0; i < s.media.size(); ++i) {
    const Medium &a = s.media[i], &b = back.media[i];
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.kind, b.kind);
    EXPECT_EQ(a.sigma_t.value, b.sigma_t.value);
    EXPECT_EQ(a.sigma_t.texture, b.sigma_t.texture);
    EXPECT_EQ(a.albedo.value, b.albedo.value);
    EXPECT_EQ(std::bit_cast<uint64_t>(a.scale), std::bit_cast<uint64_t>(b.scale));
    EXPECT_EQ(a.phase, b.phase);
    EXPECT_EQ(a.g, b.g);
    EXPECT_EQ(a.sample_emitters, b.sample_emitters);
  }
  EXPECT_EQ(back.shapes[0].interior, 0);
  EXPECT_EQ(back.shapes[0].exterior, 1);
  EXPECT_EQ(back.camera.medium, 1);
  EXPECT_EQ(write_scene_json(back), json);
  // A scene without media writes no "media" key: its file is as before media existed.
  EXPECT_EQ(write_scene_json(parse(testing::scene_with_shapes(""))).find("media"), std::string::npos);
}

TEST(NativeMedia, WriterRefusesMediaTheParserWouldRefuse) {
  Scene s = parse(fog_scene());
  s.media[0].g = 1;
  EXPECT_THROW(write_scene_json(s), SceneError);
  s = parse(fog_scene());
  s.media[0].albedo.value.x = 2;
  EXPECT_THROW(write_scene_json(s), SceneError);
  s = parse(fog_scene());
  s.shapes[0].interior = 7;
  EXPECT_THROW(write_scene_json(s), SceneError);
}

}  // namespace
}  // namespace tessera
