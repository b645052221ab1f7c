// Point, spot and directional lights: what sample() returns, and the spot's falloff against
// Mitsuba 3's (reference values from mitsuba_reference.py).
#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <string>

#include "render/light/directional_light.h"
#include "render/light/point_light.h"
#include "render/light/spot_light.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

Light light_of(LightKind kind, glm::dmat4 to_world, glm::dvec3 value) {
  Light l;
  l.kind = kind;
  l.origin = "lights[1]";
  l.to_world = to_world;
  l.value = value;
  return l;
}

TEST(PointLight, RadianceFallsWithTheSquareOfDistance) {
  const PointLight light(
      light_of(LightKind::point, glm::translate(glm::dmat4(1.0), {1, 2, 3}), {4, 8, 12}));
  const LightSample s = light.sample({1, 2, 1});
  EXPECT_TRUE(s.delta);
  EXPECT_EQ(s.pdf, 1.0f);
  EXPECT_FLOAT_EQ(s.distance, 2.0f);
  EXPECT_EQ(s.wi, glm::vec3(0, 0, 1));
  EXPECT_EQ(s.radiance, glm::vec3(1, 2, 3));
  EXPECT_EQ(s.point.p, glm::vec3(1, 2, 3));
  EXPECT_EQ(light.sample({1, 2, 3}).pdf, 0.0f);  // at the light itself: nothing, no NaN
  EXPECT_NEAR(light.power(), 4 * M_PI * (0.2126 * 4 + 0.7152 * 8 + 0.0722 * 12), 1e-4);
}

TEST(SpotLight, FalloffMatchesMitsuba) {
  Light l = light_of(LightKind::spot, glm::dmat4(1.0), {1, 1, 1});
  l.cutoff_angle_deg = 30;
  l.beam_width_deg = 20;
  const SpotLight spot(l);
  // mitsuba_reference.py (Mitsuba 3.9.1): radiance at distance 1, angle theta off the axis.
  const struct {
    float theta_deg, radiance;
  } kMitsuba[] = {
      {0.0f, 1.0f},
      {10.0f, 1.000000238418579f},
      {19.9f, 1.0f},
      {20.5f, 0.9500002861022949f},
      {22.0f, 0.8000001311302185f},
      {25.0f, 0.5000004768371582f},
      {28.0f, 0.19999973475933075f},
      {29.9f, 0.01000007800757885f},
      {30.5f, 0.0f},
      {45.0f, 0.0f},
      {120.0f, 0.0f},
  };
  for (const auto& ref : kMitsuba) {
    const float t = glm::radians(ref.theta_deg);
    const LightSample s = spot.sample({std::sin(t), 0.0f, std::cos(t)});
    EXPECT_NEAR(s.radiance.x, ref.radiance, 2e-5f) << "theta " << ref.theta_deg;
    EXPECT_EQ(s.pdf, ref.radiance > 0 ? 1.0f : 0.0f) << "theta " << ref.theta_deg;
  }
}

TEST(SpotLight, FollowsToWorldAndDistance) {
  // Placed at (0, 0, 5) shining down -z (rotated 180 degrees about x).
  glm::dmat4 to_world = glm::translate(glm::dmat4(1.0), {0, 0, 5});
  to_world = glm::rotate(to_world, glm::radians(180.0), glm::dvec3(1, 0, 0));
  Light l = light_of(LightKind::spot, to_world, {2, 2, 2});
  l.cutoff_angle_deg = 30;
  l.beam_width_deg = 20;
  const SpotLight spot(l);
  const LightSample below = spot.sample({0, 0, 1});
  EXPECT_NEAR(below.radiance.x, 2.0f / 16.0f, 1e-6f);
  EXPECT_NEAR(below.wi.z, 1.0f, 1e-6f);
  EXPECT_EQ(spot.sample({0, 0, 9}).pdf, 0.0f);  // behind it
  const float t = glm::radians(25.0f);          // half way down the ramp, distance 2
  const LightSample ramp = spot.sample({2 * std::sin(t), 0, 5 - 2 * std::cos(t)});
  EXPECT_NEAR(ramp.radiance.x, 2.0f * 0.5f / 4.0f, 1e-5f);
}

TEST(SpotLight, RefusesBeamWiderThanCutoff) {
  Light l = light_of(LightKind::spot, glm::dmat4(1.0), {1, 1, 1});
  l.cutoff_angle_deg = 20;
  l.beam_width_deg = 25;
  try {
    SpotLight spot(l);
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("lights[1]: spot light needs"), std::string::npos)
        << e.what();
  }
}

TEST(DirectionalLight, ArrivesAgainstToWorldZ) {
  // +z rotated to -y: light travels down, so wi points up.
  const glm::dmat4 to_world = glm::rotate(glm::dmat4(1.0), glm::radians(90.0), glm::dvec3(1, 0, 0));
  const DirectionalLight light(light_of(LightKind::directional, to_world, {3, 3, 3}));
  const LightSample s = light.sample();
  EXPECT_NEAR(s.wi.y, 1.0f, 1e-6f);
  EXPECT_TRUE(std::isinf(s.distance));
  EXPECT_EQ(s.radiance, glm::vec3(3, 3, 3));
  EXPECT_TRUE(s.delta);
  EXPECT_NEAR(light.power(2.0), M_PI * 4 * 3, 1e-4);
}

}  // namespace
}  // namespace tessera
