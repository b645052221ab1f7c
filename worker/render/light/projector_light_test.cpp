// The projector light against Mitsuba 3's projector emitter (reference values from
// mitsuba_projector_reference.py, in mitsuba_projector_reference.inc).
#include "render/light/projector_light.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "render/light/light_reference_setup.h"

namespace tessera {
namespace {

struct ProjectorReference {
  glm::vec3 p;         ///< world point
  glm::vec3 radiance;  ///< what Mitsuba's projector sends to it
};

#define TEXTURED_PROJECTOR
const ProjectorReference kTextured[] = {
#include "render/light/mitsuba_projector_reference.inc"
};
#undef TEXTURED_PROJECTOR
const ProjectorReference kConstant[] = {
#include "render/light/mitsuba_projector_reference.inc"
};


Light textured_projector() {
  Light l;
  l.kind = LightKind::projector;
  l.origin = "lights[0]";
  l.to_world = test::reference_light_frame();
  l.value = glm::dvec3(1.5);  // Mitsuba's scale
  l.texture = 0;
  l.fov_x_deg = 40;
  l.aspect = 4.0 / 3.0;  // the texture's width / height
  return l;
}

void expect_matches(const ProjectorLight& light, const ProjectorReference& r) {
  const LightSample s = light.sample(r.p);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(s.radiance[c], r.radiance[c], 2e-4f * r.radiance[c] + 1e-6f)
        << "point (" << r.p.x << ", " << r.p.y << ", " << r.p.z << "), channel " << c;
  }
  EXPECT_EQ(s.pdf, r.radiance.x > 0 ? 1.0f : 0.0f);
  if (s.pdf > 0) {
    EXPECT_TRUE(s.delta);
    EXPECT_NEAR(glm::length(s.wi), 1.0f, 1e-6f);
  }
}

TEST(ProjectorLight, TexturedImageMatchesMitsuba) {
  const TextureSet textures = test::reference_light_texture("slide", "slide.exr");
  const ProjectorLight light(textured_projector(), [&](int32_t texture, glm::vec2 uv) {
    return textures.lookup(texture, uv);
  });
  int lit = 0;
  for (const ProjectorReference& r : kTextured) {
    expect_matches(light, r);
    lit += r.radiance.x > 0;
  }
  EXPECT_GT(lit, 12);  // most points inside the frustum, some outside
  EXPECT_LT(lit, 24);
}

TEST(ProjectorLight, ConstantIrradianceMatchesMitsuba) {
  Light l;
  l.kind = LightKind::projector;
  l.origin = "lights[0]";
  l.value = {0.5, 1, 2};
  l.fov_x_deg = 60;
  l.aspect = 1;  // Mitsuba: a constant's resolution is 1 x 1
  const ProjectorLight light(l);
  for (const ProjectorReference& r : kConstant) expect_matches(light, r);
  // On the image plane z = 1 facing it, the irradiance is pi * value (Mitsuba's convention).
  const LightSample s = light.sample({0.2f, -0.1f, 1.0f});
  const float cos_surface = -s.wi.z;  // the plane faces the projector: normal -z
  EXPECT_NEAR(s.radiance.y * cos_surface, 3.14159265f, 1e-5f);
  // Behind it, beside it, and at it: nothing.
  EXPECT_EQ(light.sample({0, 0, -1}).pdf, 0.0f);
  EXPECT_EQ(light.sample({0.7f, 0, 1}).pdf, 0.0f);
  EXPECT_EQ(light.sample({0, 0, 0}).pdf, 0.0f);
  // Power: pi E times the image's area at z = 1, (2 tan 30)^2.
  const double side = 2 * std::tan(M_PI / 6);
  EXPECT_NEAR(light.power(), M_PI * (0.2126 * 0.5 + 0.7152 * 1 + 0.0722 * 2) * side * side, 1e-5);
}

TEST(ProjectorLight, UvFollowsMitsubasProjection) {
  Light l = textured_projector();
  l.to_world = glm::dmat4(1.0);
  const TextureSet textures = test::reference_light_texture("slide", "slide.exr");
  const ProjectorLight light(l, [&](int32_t t, glm::vec2 uv) { return textures.lookup(t, uv); });
  const float t = std::tan(glm::radians(20.0f));
  EXPECT_EQ(light.uv_of({0, 0, 2}), glm::vec2(0.5f, 0.5f));
  EXPECT_NEAR(light.uv_of({t, 0, 1}).x, 0.0f, 1e-6f);  // +x is the image's left edge
  EXPECT_NEAR(light.uv_of({0, t * 0.75f, 1}).y, 0.0f, 1e-6f);  // +y its top, at 4:3
}

TEST(ProjectorLight, BadFrustumsAreRefusedNamingTheLight) {
  Light l = textured_projector();
  l.texture = -1;
  l.fov_x_deg = 180;
  try {
    ProjectorLight light(l);
    FAIL() << "fov 180 accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("lights[0]: a projector needs 0 < fov"),
              std::string::npos);
  }
  l.fov_x_deg = 40;
  l.aspect = 0;
  EXPECT_THROW(ProjectorLight{l}, SceneError);
  EXPECT_THROW(ProjectorLight{textured_projector()}, SceneError);  // a texture, no lookup
}

}  // namespace
}  // namespace tessera
