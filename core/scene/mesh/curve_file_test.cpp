// Mitsuba's curve files: good files (curves split by empty lines, CRLF, signs, exponents) and
// every kind of bad line, each refused with the file and line.
#include "scene/mesh/curve_file.h"

#include <gtest/gtest.h>

#include <string>

#include "scene/scene_error.h"

namespace tessera {
namespace {

std::string curve_error(std::string_view text, CurveBasis basis = CurveBasis::linear) {
  try {
    parse_curve_file(text, "hair/c.txt", basis);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(CurveFile, ReadsCurvesSplitByEmptyLines) {
  // Mitsuba's own example: two curves, the second with increasing radii.
  const char* text =
      "-1.0 0.1 0.1 0.5\n"
      " 1.0 1.4 1.2 0.5\n"
      "\n"
      "-1.0 5.0 2.2 1\n"
      "-2.3 4.0 2.3 2\n"
      " 4.0 1.0 2.2 5\n"
      " 4.0 0.0 2.3 6\n";
  CurveFile file = parse_curve_file(text, "c.txt", CurveBasis::linear);
  ASSERT_EQ(file.curve_sizes, (std::vector<uint32_t>{2, 4}));
  ASSERT_EQ(file.control_points.size(), 6u);
  EXPECT_EQ(file.control_points[0], glm::dvec4(-1.0f, 0.1f, 0.1f, 0.5f));
  EXPECT_EQ(file.control_points[5], glm::dvec4(4, 0, 2.3f, 6));
}

TEST(CurveFile, BlankLinesTabsCarriageReturnsAndSigns) {
  // Several blank lines (one of spaces, one of "\r") make one break; leading blank lines and a
  // missing final newline are fine; '+' and exponents parse as strtof does.
  const char* text =
      "\n \t\r\n"
      "0\t0 0 +1e-1\r\n"
      "1 0 0 0.1\r\n"
      "\r\n"
      "  \n"
      "0 1 0 0\n"
      "0 2 0 2.5e0\n"
      "0 3 0 0\n"
      "0 4 0 0";
  CurveFile file = parse_curve_file(text, "c.txt", CurveBasis::linear);
  ASSERT_EQ(file.curve_sizes, (std::vector<uint32_t>{2, 4}));
  EXPECT_EQ(file.control_points[0].w, double(0.1f));
  EXPECT_EQ(file.control_points[3], glm::dvec4(0, 2, 0, 2.5));
  EXPECT_EQ(file.control_points[5], glm::dvec4(0, 4, 0, 0));
}

TEST(CurveFile, RoundsToFloatAsMitsuba) {
  CurveFile file = parse_curve_file("0.1 0.2 0.3 0.4\n1 1 1 1\n", "c.txt", CurveBasis::linear);
  EXPECT_EQ(file.control_points[0], glm::dvec4(0.1f, 0.2f, 0.3f, 0.4f));
}

TEST(CurveFile, TooFewPointsNamesTheCurvesFirstLine) {
  EXPECT_EQ(curve_error("0 0 0 1\n1 0 0 1\n\n2 0 0 1\n"),
            "hair/c.txt: line 4: a linear curve needs at least 2 control points (this one has 1; "
            "an empty line starts a new curve)");
  EXPECT_EQ(curve_error("0 0 0 1\n1 0 0 1\n2 0 0 1\n", CurveBasis::bspline),
            "hair/c.txt: line 1: a B-spline curve needs at least 4 control points (this one has "
            "3; an empty line starts a new curve)");
  // Four points make one B-spline segment.
  EXPECT_EQ(parse_curve_file("0 0 0 1\n1 0 0 1\n2 0 0 1\n3 0 0 1\n", "c", CurveBasis::bspline)
                .curve_sizes,
            (std::vector<uint32_t>{4}));
}

TEST(CurveFile, BadLinesNameFileAndLine) {
  EXPECT_EQ(curve_error("0 0 0 1\n1 0 0\n"),
            "hair/c.txt: line 2: \"1 0 0\": expected four numbers \"x y z radius\" (Mitsuba's "
            "curve format)");
  EXPECT_EQ(curve_error("0 0 0 1\n1 0 x 1\n"),
            "hair/c.txt: line 2: \"1 0 x 1\": expected four numbers \"x y z radius\" (Mitsuba's "
            "curve format)");
  EXPECT_EQ(curve_error("0 0 0 1\n1,0,0,1\n"),
            "hair/c.txt: line 2: \"1,0,0,1\": expected four numbers \"x y z radius\" (Mitsuba's "
            "curve format)");
  EXPECT_EQ(curve_error("0 0 0 1 5\n1 0 0 1\n"),
            "hair/c.txt: line 1: \"0 0 0 1 5\": more than four numbers \"x y z radius\" on a line");
  EXPECT_EQ(curve_error("# comment\n"),
            "hair/c.txt: line 1: \"# comment\": expected four numbers \"x y z radius\" (Mitsuba's "
            "curve format)");
  EXPECT_EQ(curve_error("0 0 0 1\n1 0 0 -0.5\n"),
            "hair/c.txt: line 2: the radius must be finite and >= 0 (got -0.5)");
  EXPECT_EQ(curve_error("0 0 0 1\n1 0 0 nan\n"),
            "hair/c.txt: line 2: the radius must be finite and >= 0 (got nan)");
  EXPECT_EQ(curve_error("0 inf 0 1\n1 0 0 1\n"), "hair/c.txt: line 1: the position is not finite");
  EXPECT_EQ(curve_error("0 1e39 0 1\n1 0 0 1\n"),
            "hair/c.txt: line 1: \"0 1e39 0 1\": a number out of float range");
}

TEST(CurveFile, EmptyFileIsRefused) {
  EXPECT_EQ(curve_error(""), "hair/c.txt: no control points (an empty curve file)");
  EXPECT_EQ(curve_error("\n  \n\r\n"), "hair/c.txt: no control points (an empty curve file)");
}

}  // namespace
}  // namespace tessera
