// Mitsuba's <transform>: every operation, their composition order, and bad input.
#include "scene/mitsuba/mitsuba_transform.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "scene/mitsuba/mitsuba_test_support.h"
#include "scene/mitsuba/mitsuba_xml_document.h"

namespace tessera {
namespace {

using testing::expect_near;
using testing::memory_reader;

/// The <transform> holding `operations`, read.
Transform transform_of(const std::string& operations) {
  MitsubaDocument d =
      read_mitsuba_document("<scene version=\"3.0.0\">\n<transform name=\"to_world\">\n" +
                                operations + "\n</transform>\n</scene>",
                            "t.xml", memory_reader({}));
  return read_mitsuba_transform(d.scene.children.at(0));
}

glm::dvec3 moved(const glm::dvec3& p, const std::string& operations) {
  return transform_of(operations).point(p);
}

std::string transform_error(const std::string& operations) {
  try {
    transform_of(operations);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(MitsubaTransform, Translate) {
  expect_near(moved({1, 2, 3}, R"(<translate x="1" y="-2" z="0.5"/>)"), {2, 0, 3.5});
  expect_near(moved({1, 2, 3}, R"(<translate y="1"/>)"), {1, 3, 3});  // missing ones are 0
  expect_near(moved({1, 2, 3}, R"(<translate value="1, 1, 1"/>)"), {2, 3, 4});
  expect_near(moved({1, 2, 3}, R"(<translate value="1 1 1"/>)"), {2, 3, 4});
  expect_near(moved({1, 2, 3}, R"(<translate value="2"/>)"), {3, 4, 5});
}

TEST(MitsubaTransform, Scale) {
  expect_near(moved({1, 2, 3}, R"(<scale value="2"/>)"), {2, 4, 6});
  expect_near(moved({1, 2, 3}, R"(<scale value="1, -1, 0.5"/>)"), {1, -2, 1.5});
  expect_near(moved({1, 2, 3}, R"(<scale x="3"/>)"), {3, 2, 3});  // missing ones are 1
  expect_near(moved({1, 2, 3}, R"(<scale x="2" y="3" z="4"/>)"), {2, 6, 12});
}

TEST(MitsubaTransform, RotateIsRightHandedInDegrees) {
  expect_near(moved({1, 0, 0}, R"(<rotate z="1" angle="90"/>)"), {0, 1, 0}, 1e-15);
  expect_near(moved({0, 1, 0}, R"(<rotate x="1" angle="90"/>)"), {0, 0, 1}, 1e-15);
  expect_near(moved({0, 0, 1}, R"(<rotate y="1" angle="90"/>)"), {1, 0, 0}, 1e-15);
  // value="x, y, z" works too.
  expect_near(moved({1, 0, 0}, R"(<rotate value="0, 0, 1" angle="-90"/>)"), {0, -1, 0}, 1e-15);
  const double d = 1 / std::sqrt(3.0);
  glm::dvec3 p = moved({1, 0, 0}, "<rotate x=\"" + std::to_string(d) + "\" y=\"" +
                                      std::to_string(d) + "\" z=\"" + std::to_string(d) +
                                      "\" angle=\"120\"/>");
  expect_near(p, {0, 1, 0}, 1e-6);  // a third of a turn about the diagonal cycles the axes
}

/// Mitsuba 3's rotation matrix (drjit's rotate, which Transform4f::rotate calls with the axis
/// as the XML gives it): c I + (1 - c) a a^T + s [a]x, a not normalised.
glm::dmat3 mitsuba_formula(const glm::dvec3& a, double degrees) {
  const double t = degrees * std::acos(-1.0) / 180, c = std::cos(t), s = std::sin(t);
  glm::dmat3 cross(0.0);  // [a]x, column-major
  cross[1][0] = -a.z, cross[2][0] = a.y, cross[0][1] = a.z;
  cross[2][1] = -a.x, cross[0][2] = -a.y, cross[1][2] = a.x;
  return c * glm::dmat3(1.0) + (1 - c) * glm::outerProduct(a, a) + s * cross;
}

TEST(MitsubaTransform, ANonUnitAxisIsUsedAsWrittenAsMitsubaDoes) {
  // mitsuba-data's scenes/hello.xml turns its teapot about (0, 1, 1): Mitsuba 3.9.1 does not
  // normalise, so the matrix scales and shears as well as it turns.
  for (const auto& [axis, angle] : {std::pair{glm::dvec3(0, 1, 1), 15.0},
                                    std::pair{glm::dvec3(0, 0, 5), -90.0},
                                    std::pair{glm::dvec3(1, 1, 1), 120.0},
                                    std::pair{glm::dvec3(0.2, -0.3, 0.1), 40.0}}) {
    const std::string op = "<rotate x=\"" + std::to_string(axis.x) + "\" y=\"" +
                           std::to_string(axis.y) + "\" z=\"" + std::to_string(axis.z) +
                           "\" angle=\"" + std::to_string(angle) + "\"/>";
    const glm::dmat4 m = transform_of(op).matrix();
    const glm::dmat3 expected = mitsuba_formula(axis, angle);
    for (int c = 0; c < 3; ++c) {
      for (int r = 0; r < 3; ++r) EXPECT_NEAR(m[c][r], expected[c][r], 1e-14) << op;
      EXPECT_EQ(m[3][c], 0) << op;
    }
  }
  // The axis (0, 0, 5) scales by 25 along it and by 5 across it.
  expect_near(moved({1, 0, 0}, R"(<rotate value="0, 0, 5" angle="-90"/>)"), {0, -5, 0}, 1e-14);
  expect_near(moved({0, 0, 1}, R"(<rotate value="0, 0, 5" angle="-90"/>)"), {0, 0, 25}, 1e-14);
}

TEST(MitsubaTransform, ANonUnitAxisIsNoted) {
  ::testing::internal::CaptureStderr();
  transform_of(R"(<rotate x="0.0" y="1.0" z="1.0" angle="15"/>)");
  const std::string noted = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(noted,
            "note: t.xml: line 3: <rotate>: the rotation axis (0, 1, 1) is not of unit length "
            "(length 1.41421): Mitsuba 3 builds the matrix from the axis as written, which "
            "scales and shears as well as it turns, and so does Tessera\n");
  ::testing::internal::CaptureStderr();
  transform_of(R"(<rotate y="1" angle="15"/><rotate x="0.6" y="0.8" angle="15"/>)");
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
}

TEST(MitsubaTransform, Matrix16IsRowMajor) {
  expect_near(moved({1, 2, 3}, R"(<matrix value="1 0 0 5  0 1 0 6  0 0 1 7  0 0 0 1"/>)"),
              {6, 8, 10});
  expect_near(moved({1, 0, 0}, R"(<matrix value="0,-1,0,0, 1,0,0,0, 0,0,1,0, 0,0,0,1"/>)"),
              {0, 1, 0});
}

TEST(MitsubaTransform, Matrix9IsTheLinearPart) {
  expect_near(moved({1, 2, 3}, R"(<matrix value="2 0 0 0 3 0 0 0 4"/>)"), {2, 6, 12});
  expect_near(moved({1, 0, 0}, R"(<matrix value="0 -1 0 1 0 0 0 0 1"/>)"), {0, 1, 0});
}

TEST(MitsubaTransform, LookAtIsMitsubasFrame) {
  // Columns (left, up, dir, origin): local +z runs from origin to target, +y is up, and local +x
  // is up x dir ("left", seen from behind the camera).
  Transform t = transform_of(R"(<lookat origin="1, 2, 3" target="1, 2, 0" up="0, 1, 0"/>)");
  expect_near(t.point({0, 0, 0}), {1, 2, 3});
  expect_near(t.point({0, 0, 1}), {1, 2, 2});                        // toward the target
  expect_near(t.point({0, 1, 0}) - t.point({0, 0, 0}), {0, 1, 0});   // up
  expect_near(t.point({1, 0, 0}) - t.point({0, 0, 0}), {-1, 0, 0});  // left = up x dir
  EXPECT_GT(t.determinant(), 0);
}

TEST(MitsubaTransform, LookAtWithoutUpPicksAPerpendicularOne) {
  Transform t = transform_of(R"(<lookat origin="0, 0, 0" target="0.3, -0.2, 2"/>)");
  glm::dvec3 dir = t.point({0, 0, 1});
  glm::dvec3 up = t.point({0, 1, 0});
  EXPECT_NEAR(glm::dot(dir, up), 0, 1e-12);
  EXPECT_NEAR(glm::length(up), 1, 1e-12);
  expect_near(dir, glm::normalize(glm::dvec3(0.3, -0.2, 2)), 1e-12);
}

TEST(MitsubaTransform, EachNewOperationIsAppliedAfterThoseBefore) {
  // Mitsuba left-multiplies: <translate/><scale/> scales the translated point.
  expect_near(moved({1, 0, 0}, R"(<translate x="1"/><scale value="2"/>)"), {4, 0, 0});
  expect_near(moved({1, 0, 0}, R"(<scale value="2"/><translate x="1"/>)"), {3, 0, 0});
  expect_near(moved({1, 0, 0}, R"(<rotate z="1" angle="90"/><translate z="5"/>)"), {0, 1, 5},
              1e-15);
  expect_near(moved({1, 0, 0}, R"(<translate z="5"/><rotate y="1" angle="90"/>)"), {5, 0, -1},
              1e-15);
  // A lookat after a scale places the scaled object.
  expect_near(moved({0, 0, 1}, R"(<scale value="2"/><lookat origin="0,0,0" target="1,0,0"/>)"),
              {2, 0, 0}, 1e-15);
}

TEST(MitsubaTransform, AnEmptyTransformIsTheIdentity) {
  expect_near(moved({1, 2, 3}, ""), {1, 2, 3});
}

TEST(MitsubaTransform, BadOperationsNameTheirLine) {
  EXPECT_EQ(transform_error(R"(<translate x="1" value="1,2,3"/>)"),
            "t.xml: line 3: <translate>: give either value or x/y/z, not both");
  EXPECT_EQ(transform_error(R"(<translate value="1, 2"/>)"),
            "t.xml: line 3: <translate>: value must be one number or three (got \"1, 2\")");
  EXPECT_EQ(transform_error(R"(<translate x="one"/>)"),
            "t.xml: line 3: <translate>: x must be a number (got \"one\")");
  EXPECT_EQ(transform_error(R"(<scale value="0"/>)"),
            "t.xml: line 3: <scale>: scale factors must be non-zero");
  EXPECT_EQ(transform_error(R"(<rotate x="1"/>)"),
            "t.xml: line 3: <rotate>: missing attribute \"angle\" (degrees)");
  EXPECT_EQ(transform_error(R"(<rotate angle="10"/>)"),
            "t.xml: line 3: <rotate>: the rotation axis must not be zero");
  EXPECT_EQ(transform_error(R"(<matrix value="1 0 0"/>)"),
            "t.xml: line 3: <matrix>: value must have 16 numbers (or 9), got 3");
  EXPECT_EQ(transform_error(R"(<matrix value="1 0 0 0 0 1 0 0 0 0 1 0 0 0 1 1"/>)"),
            "t.xml: line 3: <matrix>: the last row must be 0 0 0 1 (Tessera takes affine "
            "transforms only)");
  EXPECT_EQ(transform_error(R"(<matrix value="1 0 0 0 0 1 0 0 0 0 0 0 0 0 0 1"/>)"),
            "t.xml: line 2: <transform name=\"to_world\">: the composed transform is singular "
            "(not invertible)");
  EXPECT_EQ(transform_error(R"(<lookat origin="0,0,0" target="0,0,0"/>)"),
            "t.xml: line 3: <lookat>: undefined: origin equals target, or up is parallel to "
            "the view direction");
  EXPECT_EQ(transform_error(R"(<lookat origin="0,0,0" target="0,1,0" up="0,1,0"/>)"),
            "t.xml: line 3: <lookat>: undefined: origin equals target, or up is parallel to "
            "the view direction");
  EXPECT_EQ(transform_error(R"(<lookat origin="0,0,0"/>)"),
            "t.xml: line 3: <lookat>: missing attribute \"target\"");
  EXPECT_EQ(transform_error(R"(<skew value="1"/>)"),
            "t.xml: line 3: <skew>: not a transform operation (Tessera reads translate, rotate, "
            "scale, matrix and lookat)");
  EXPECT_EQ(transform_error(R"(<translate x="1e999"/>)"),
            "t.xml: line 3: <translate>: x must be a number (got \"1e999\")");
  EXPECT_EQ(transform_error(R"(<scale value="1e300"/><scale value="1e300"/>)"),
            "t.xml: line 2: <transform name=\"to_world\">: the composed transform overflows");
}

TEST(MitsubaTransform, MirrorsAreAllowedAndReported) {
  Transform t = transform_of(R"(<scale x="-1"/>)");
  EXPECT_TRUE(t.flips_orientation());
}

}  // namespace
}  // namespace tessera
