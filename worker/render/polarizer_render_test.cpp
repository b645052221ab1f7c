// The polarizer through the whole renderer: a polarizing sphere inside a constant environment.
// Every camera ray that meets the sphere crosses it twice and goes on to the sky, so its pixel
// is exactly (transmittance / 2)^2 of the sky (no noise: only delta lobes), from both sides,
// and the background is the sky.
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <gtest/gtest.h>

#include "accum/film.h"
#include "render/renderer.h"
#include "render/test_statistics.h"
#include "render/testing/test_scenes.h"

namespace tessera {
namespace {

TEST(PolarizerRender, ASphereShowsAQuarterOfTheSkyPerChannelSquared) {
  Scene s;
  s.camera.position = {0, 0, 4};
  s.camera.look_at = {0, 0, 0};
  s.camera.fov_deg = 30;
  Material m;
  m.name = "polarizer";
  m.type = MaterialType::polarizer;
  m.specular_transmittance.value = {1.0, 0.8, 0.4};
  s.materials.push_back(m);
  s.shapes.push_back(test::sphere({0, 0, 0}, 1, 0));
  Light sky;
  sky.kind = LightKind::constant;
  sky.value = glm::dvec3(0.7);
  s.lights.push_back(sky);

  const int size = 16;
  const Renderer renderer(s, test::test_job(size, size, 4));
  const Accumulation acc = renderer.render({0, 0, size, size}, 0, 4, nullptr);
  ASSERT_TRUE(test::all_finite(acc));
  const glm::dvec3 expected[] = {{0.7, 0.7, 0.7}, 0.7 * glm::dvec3(0.25, 0.16, 0.04)};
  int inside = 0, outside = 0;
  for (size_t i = 0; i < acc.pixels(); ++i) {
    const glm::dvec3 c = glm::dvec3(acc.rgb[3 * i], acc.rgb[3 * i + 1], acc.rgb[3 * i + 2]) /
                         double(acc.count[i]);
    // Pixels on the sphere's outline mix both; the centre and the corners do not.
    const bool centre = glm::distance(glm::dvec2(i % size, i / size), glm::dvec2(7.5)) < 3;
    const bool corner = glm::distance(glm::dvec2(i % size, i / size), glm::dvec2(7.5)) > 10;
    if (!centre && !corner) continue;
    const glm::dvec3& e = expected[centre ? 1 : 0];
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], e[k], 1e-5) << "pixel " << i << " channel " << k;
    ++(centre ? inside : outside);
  }
  EXPECT_GT(inside, 0);
  EXPECT_GT(outside, 0);
}

}  // namespace
}  // namespace tessera
