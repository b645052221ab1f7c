// "curves" shapes of the native format: inline and file-based, the transform's rule for radii,
// each error naming its JSON path (and the file's line), and the writer's exact round trip.
#include "scene/native/curve_shape.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "scene/native/scene_writer.h"
#include "scene/native/native_test_support.h"

namespace tessera {
namespace {

using testing::error_of;
using testing::parse;
using testing::scene_with_shapes;

const char* kTwoCurves = "0 0 0 0.1\n1 0 0 0.2\n\n0 1 0 0.1\n1 1 0 0.1\n2 1 0 0.3\n";

TEST(CurveShape, ReadsACurveFileAndMovesOnlyThePositions) {
  Scene s = parse(scene_with_shapes(R"({"type": "curves", "basis": "linear", "file": "c.txt",
      "material": "white", "transform": {"scale": 2, "translate": [0, 0, 5]}})"),
                  {{"c.txt", kTwoCurves}});
  ASSERT_EQ(s.shapes.size(), 1u);
  const Shape& shape = s.shapes[0];
  EXPECT_EQ(shape.kind, Shape::Kind::curves);
  EXPECT_EQ(shape.curve_basis, CurveBasis::linear);
  EXPECT_EQ(shape.curve_sizes, (std::vector<uint32_t>{2, 3}));
  ASSERT_EQ(shape.control_points.size(), 5u);
  // Mitsuba's rule: to_world moves the points, the radii stay as the file gives them.
  EXPECT_EQ(shape.control_points[1], glm::dvec4(2, 0, 5, double(0.2f)));
  EXPECT_EQ(shape.control_points[4], glm::dvec4(4, 2, 5, double(0.3f)));
  EXPECT_EQ(s.referenced_files, (std::vector<std::string>{"c.txt"}));
}

TEST(CurveShape, ReadsInlineControlPoints) {
  Scene s = parse(scene_with_shapes(R"({"type": "curves", "basis": "bspline", "material": "white",
      "control_points": [[0, 0, 0, 1], [1, 0, 0, 1], [2, 0, 0, 1], [3, 0, 0, 0.5], [4, 0, 0, 0]]})"));
  const Shape& shape = s.shapes[0];
  EXPECT_EQ(shape.curve_basis, CurveBasis::bspline);
  EXPECT_EQ(shape.curve_sizes, (std::vector<uint32_t>{5}));
  EXPECT_EQ(shape.control_points[3], glm::dvec4(3, 0, 0, 0.5));
}

TEST(CurveShape, ErrorsNameThePath) {
  const std::map<std::string, std::string> files = {{"c.txt", kTwoCurves},
                                                    {"bad.txt", "0 0 0 1\n1 0 0\n"}};
  auto shape_error = [&](const std::string& shape) {
    return error_of(scene_with_shapes(shape), files);
  };
  EXPECT_EQ(shape_error(R"({"type": "curves", "basis": "cubic", "file": "c.txt", "material": "white"})"),
            "shapes[0].basis: unknown curve basis \"cubic\" (expected linear or bspline)");
  EXPECT_EQ(shape_error(R"({"type": "curves", "file": "bad.txt", "material": "white"})"),
            "shapes[0].file: bad.txt: line 2: \"1 0 0\": expected four numbers \"x y z radius\" "
            "(Mitsuba's curve format)");
  EXPECT_EQ(shape_error(R"({"type": "curves", "file": "none.txt", "material": "white"})"),
            "shapes[0].file: none.txt: no such file in the scene's folder");
  EXPECT_EQ(shape_error(R"({"type": "curves", "basis": "bspline", "file": "c.txt", "material": "white"})"),
            "shapes[0].file: c.txt: line 1: a B-spline curve needs at least 4 control points (this "
            "one has 2; an empty line starts a new curve)");
  EXPECT_EQ(shape_error(R"({"type": "curves", "material": "white"})"),
            "shapes[0]: a \"curves\" shape gives either \"file\" or \"control_points\"");
  EXPECT_EQ(shape_error(R"({"type": "curves", "file": "c.txt"})"),
            "shapes[0].material: required (curves cannot emit light)");
  EXPECT_EQ(shape_error(R"({"type": "curves", "file": "c.txt", "material": "white", "emission": [1, 1, 1]})")
                .substr(0, 35),
            "shapes[0].emission: unknown key (a ");
  EXPECT_EQ(shape_error(R"({"type": "curves", "material": "white",
      "control_points": [[0, 0, 0, 1], [1, 0, 0, -1]]})"),
            "shapes[0].control_points[1][3]: a radius must be >= 0 (got -1)");
  EXPECT_EQ(shape_error(R"({"type": "curves", "material": "white",
      "control_points": [[0, 0, 0, 1], [1, 0, 0]]})"),
            "shapes[0].control_points[1]: must have 4 elements (got 3)");
  EXPECT_EQ(shape_error(R"({"type": "curves", "material": "white",
      "control_points": [[0, 0, 0, 1], [1, 0, 0, 1], [2, 0, 0, 1]], "curve_sizes": [2, 2]})"),
            "shapes[0].curve_sizes: the curves have 4 control points in all, but 3 are given");
  EXPECT_EQ(shape_error(R"({"type": "curves", "material": "white",
      "control_points": [[0, 0, 0, 1], [1, 0, 0, 1], [2, 0, 0, 1]], "curve_sizes": [1, 2]})"),
            "shapes[0].curve_sizes[0]: must be in [2, 4294967295] (got 1)");
  EXPECT_EQ(shape_error(R"({"type": "curves", "material": "white", "basis": "bspline",
      "control_points": [[0, 0, 0, 1], [1, 0, 0, 1], [2, 0, 0, 1]]})"),
            "shapes[0].control_points: a bspline curve needs at least 4 control points");
  EXPECT_EQ(shape_error(R"({"type": "curves", "file": "c.txt", "material": "white",
      "transform": {"scale": 1e300}, "curve_sizes": [2, 3]})"),
            "shapes[0].curve_sizes: only with \"control_points\"");
  EXPECT_EQ(shape_error(R"({"type": "curves", "file": "c.txt", "material": "white",
      "transform": {"scale": [1e308, 1, 1], "translate": [1.7e308, 0, 0]}})"),
            "shapes[0].transform: a control point overflows after the transform");
}

TEST(CurveShape, WriterRoundTripsExactly) {
  Scene s = parse(scene_with_shapes(R"({"type": "curves", "basis": "bspline", "file": "c.txt",
      "material": "white", "two_sided": true, "transform": {"rotate": {"axis": [1, 2, 3], "angle": 31}}})"),
                  {{"c.txt", "0.1 -0 0.3 0.001\n1e-7 2 3 0.5\n-1 -2 -3 0\n4 5 6 7.25\n"}});
  s.shapes[0].control_points[0].y = -0.0;  // -0 stays -0
  std::string json = write_scene_json(s);
  Scene back = parse_scene(json, testing::memory_reader({}));
  ASSERT_EQ(back.shapes.size(), 1u);
  const Shape &a = s.shapes[0], &b = back.shapes[0];
  EXPECT_EQ(b.kind, Shape::Kind::curves);
  EXPECT_EQ(b.curve_basis, CurveBasis::bspline);
  EXPECT_EQ(b.curve_sizes, a.curve_sizes);
  EXPECT_EQ(b.material, a.material);
  EXPECT_TRUE(back.materials[b.material].two_sided);
  ASSERT_EQ(b.control_points.size(), a.control_points.size());
  for (size_t k = 0; k < a.control_points.size(); ++k) {
    EXPECT_EQ(std::memcmp(&a.control_points[k], &b.control_points[k], sizeof(glm::dvec4)), 0)
        << "point " << k;
  }
  EXPECT_TRUE(std::signbit(b.control_points[0].y));
  EXPECT_EQ(write_scene_json(back), json);
}

}  // namespace
}  // namespace tessera
