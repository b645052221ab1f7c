// Curves through the Renderer: an analytic render of a tube under a directional light.
#include <cmath>

#include <gtest/gtest.h>

#include "render/renderer.h"
#include "render/test_statistics.h"
#include "render/testing/test_scenes.h"

namespace tessera {
namespace {

TEST(Curve, DirectionalLightOnATubeGivesLambertsCosine) {
  // An orthographic camera looks down -z at a tube along x of radius 1 lit from +z: the pixel
  // row at height y sees the normal (0, y, sqrt(1 - y^2)), so radiance rho E n_z / pi.
  for (CurveBasis basis : {CurveBasis::linear, CurveBasis::bspline}) {
    Scene s;
    const uint32_t m = test::add_diffuse(s, {0.5, 0.5, 0.5});
    s.shapes.push_back(test::curve(basis, {{-4, 0, 0, 1}, {-2, 0, 0, 1}, {2, 0, 0, 1}, {4, 0, 0, 1}}, m));
    s.camera.projection = Projection::orthographic;
    s.camera.position = {0, 0, 5};
    s.camera.look_at = {0, 0, 0};
    s.camera.view_size = {2, 2};
    Light sun;
    sun.kind = LightKind::directional;
    sun.to_world = glm::dmat4(1.0);
    sun.to_world[1] = glm::dvec4(0, -1, 0, 0);  // half a turn about x: light travels along -z
    sun.to_world[2] = glm::dvec4(0, 0, -1, 0);
    sun.value = glm::dvec3(3.0);
    s.lights.push_back(sun);
    const int size = 16;
    const Renderer renderer(s, test::test_job(size, size, 64));
    const Accumulation acc = renderer.render({0, 0, size, size}, 0, 64, nullptr);
    ASSERT_TRUE(test::all_finite(acc));
    for (int row = 1; row < size - 1; ++row) {
      // The pixel row spans y in [y0, y1]: the mean of n_z = sqrt(1 - y^2) over it.
      const double y1 = 1 - 2.0 * row / size, y0 = y1 - 2.0 / size;
      auto integral = [](double y) { return 0.5 * (y * std::sqrt(1 - y * y) + std::asin(y)); };
      const double expected = 0.5 * 3.0 / M_PI * (integral(y1) - integral(y0)) / (y1 - y0);
      const size_t i = size_t(row) * size + size / 2;
      const double got = acc.rgb[3 * i] / double(acc.count[i]);
      EXPECT_NEAR(got, expected, 0.03 * expected) << "row " << row;
    }
  }
}

}  // namespace
}  // namespace tessera
