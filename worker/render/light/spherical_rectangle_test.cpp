// The spherical rectangle: its solid angle against closed forms (centred, far off, in the
// plane) and its map staying on the rectangle at the corners of the unit square.
#include "render/light/spherical_rectangle.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>

namespace tessera {
namespace {

TEST(SphericalRectangle, SolidAngleMatchesClosedForms) {
  // An a x b rectangle centred at distance d: 4 asin(a b / sqrt((a^2 + 4 d^2)(b^2 + 4 d^2))).
  for (const double d : {0.01, 0.5, 2.0, 100.0}) {
    const double a = 2.0, b = 0.5;
    const SphericalRectangle r({0.3, -0.2, d + 1.0}, {0.3 - a / 2, -0.2 - b / 2, 1.0},
                               {a, 0, 0}, {0, b, 0});
    const double expected =
        4 * std::asin(a * b / std::sqrt((a * a + 4 * d * d) * (b * b + 4 * d * d)));
    EXPECT_NEAR(r.solid_angle(), expected, 1e-12 * expected + 1e-15) << d;
    EXPECT_NEAR(r.plane_distance(), d, 1e-12);
  }
  // Small and far off to the side: area x cos / distance^2 to first order.
  const glm::dvec3 ref(0, 0, 0), corner(1000, 700, 300);
  const SphericalRectangle far(ref, corner, {0.01, 0, 0}, {0, 0.01, 0});
  const glm::dvec3 c = corner + glm::dvec3(0.005, 0.005, 0);
  const double approx = 1e-4 * (c.z / glm::length(c)) / glm::dot(c, c);
  EXPECT_NEAR(far.solid_angle(), approx, 1e-4 * approx);
  // In its plane: nothing.
  EXPECT_EQ(SphericalRectangle({5, 0, 1}, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}).solid_angle(), 0.0);
}

TEST(SphericalRectangle, SamplesStayOnTheRectangle) {
  const SphericalRectangle r({0.2, 0.1, -0.7}, {-1, -1, 0}, {2, 0, 0}, {0, 1.5, 0});
  const float one = 0.99999994f;  // the largest float below 1
  for (const glm::vec2 u : {glm::vec2(0, 0), glm::vec2(one, one), glm::vec2(0, one),
                            glm::vec2(one, 0), glm::vec2(0.5f, 0.5f)}) {
    const glm::dvec2 ab = r.sample(u);
    EXPECT_TRUE(ab.x >= 0 && ab.x <= 1 && ab.y >= 0 && ab.y <= 1) << ab.x << " " << ab.y;
  }
  // u = (0, 0) and (1, 1) map to the corners at the ends of the sweep.
  EXPECT_NEAR(r.sample({0, 0}).x, 0.0, 1e-9);
  EXPECT_NEAR(r.sample({0.99999994f, 0.99999994f}).x, 1.0, 1e-6);
}

}  // namespace
}  // namespace tessera
