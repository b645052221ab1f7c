// The spot light's texture, projected over its cone, against Mitsuba 3's spot emitter
// (reference values from mitsuba_spot_reference.py, in mitsuba_spot_reference.inc).
#include "render/light/spot_light.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "render/light/light_reference_setup.h"
#include "scene/mitsuba/mitsuba_xml_loader.h"

namespace tessera {
namespace {

struct SpotReference {
  glm::vec3 p;         ///< world point
  glm::vec3 radiance;  ///< what Mitsuba's spot sends to it
};

const SpotReference kMitsuba[] = {
#include "render/light/mitsuba_spot_reference.inc"
};


Light reference_spot() {
  Light l;
  l.kind = LightKind::spot;
  l.origin = "lights[0]";
  l.to_world = test::reference_light_frame();
  l.value = {2, 3, 4};
  l.cutoff_angle_deg = 30;
  l.beam_width_deg = 20;
  l.texture = 0;
  return l;
}

TEST(SpotLight, TextureOverTheConeMatchesMitsuba) {
  const TextureSet textures = test::reference_light_texture("spot", "spot.exr");
  const SpotLight spot(reference_spot(),
                       [&](int32_t texture, glm::vec2 uv) { return textures.lookup(texture, uv); });
  for (const SpotReference& r : kMitsuba) {
    const LightSample s = spot.sample(r.p);
    for (int c = 0; c < 3; ++c) {
      // float32 in both; the falloff's acos and the frame's rotation round differently.
      EXPECT_NEAR(s.radiance[c], r.radiance[c], 2e-4f * r.radiance[c] + 1e-6f)
          << "point (" << r.p.x << ", " << r.p.y << ", " << r.p.z << "), channel " << c;
    }
    EXPECT_EQ(s.pdf, r.radiance.x > 0 ? 1.0f : 0.0f);
  }
}

TEST(SpotLight, UvSpansTheConeAcrossTheTexture) {
  const TextureSet textures = test::reference_light_texture("spot", "spot.exr");
  Light l = reference_spot();
  l.to_world = glm::dmat4(1.0);
  const SpotLight spot(l, [&](int32_t texture, glm::vec2 uv) { return textures.lookup(texture, uv); });
  const float t = std::tan(glm::radians(30.0f));
  EXPECT_EQ(spot.uv_of({0, 0, 1}), glm::vec2(0.5f, 0.5f));
  // The cutoff cone touches the square's edges: +x at u = 1, +y at v = 1.
  EXPECT_NEAR(spot.uv_of({t, 0, 1}).x, 1.0f, 1e-6f);
  EXPECT_NEAR(spot.uv_of({0, -t, 1}).y, 0.0f, 1e-6f);
  EXPECT_NEAR(spot.uv_of({2 * t, 0, 2}).x, 1.0f, 1e-6f);  // any length
  // The texture scales the light picker's power by its mean over the disc, never to 0 here.
  Light plain = l;
  plain.texture = -1;
  const double ratio = spot.power() / SpotLight(plain).power();
  EXPECT_GT(ratio, 1.0);  // texels above 1 in red weigh most in luminance
  EXPECT_LT(ratio, 12.0);
}

struct GreyReference {
  glm::vec3 p;
  float radiance;
};

const GreyReference kMitsubaGrey[] = {
#include "render/light/mitsuba_spot_srgb_reference.inc"
};

// The published emitter_spot_texture scene's kind of spot, read by the importer: an 8-bit grey
// sRGB image (decoded per texel, then interpolated, as Mitsuba does) and a lookat frame whose up
// is -x. Its points sample the whole cone, the falloff ramp and beyond.
TEST(SpotLight, GreySrgbTextureAndLookatFrameMatchMitsuba) {
  const Scene scene = parse_mitsuba_scene(R"(<scene version="3.0.0">
      <sensor type="perspective"><float name="fov" value="40"/></sensor><emitter type="spot">
      <rgb name="intensity" value="200"/><float name="cutoff_angle" value="20"/>
      <texture name="texture" type="bitmap"><string name="filename" value="grey.png"/></texture>
      <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="-1, 0, 0"/>
      </transform></emitter></scene>)",
                                          "spot.xml", test::memory_reader({{"grey.png", ""}}));
  std::vector<uint8_t> codes;
  for (int y = 0; y < 5; ++y) {
    for (int x = 0; x < 7; ++x) codes.push_back(uint8_t((37 * x + 91 * y + 11) % 256));
  }
  const TextureSet textures(
      scene.textures,
      test::memory_reader({{"grey.png", test::encode_image("grey.png", 7, 5, 1, codes,
                                                           OIIO::TypeDesc::UINT8)}}));
  const SpotLight spot(scene.lights.at(0), [&](int32_t texture, glm::vec2 uv) {
    return textures.lookup(texture, uv);
  });
  for (const GreyReference& r : kMitsubaGrey) {
    const LightSample s = spot.sample(r.p);
    for (int c = 0; c < 3; ++c) {
      // float32 in both; just inside the cutoff the falloff ramp turns the acos's rounding
      // (1e-7 rad) into 1e-5 of the peak radiance (about 2 here).
      EXPECT_NEAR(s.radiance[c], r.radiance, 2e-4f * r.radiance + 1e-5f)
          << "point (" << r.p.x << ", " << r.p.y << "), channel " << c;
    }
  }
}

TEST(SpotLight, ATextureNeedsALookup) {
  EXPECT_THROW(SpotLight{reference_spot()}, SceneError);
}

}  // namespace
}  // namespace tessera
