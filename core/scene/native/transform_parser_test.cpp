// Transforms of shapes: each kind, their order, matrices, and mirrors keeping the front.
#include <gtest/gtest.h>

#include <cmath>

#include "scene/native/native_test_support.h"

namespace tessera {
namespace {

using testing::error_of;
using testing::expect_near;
using testing::face_normal;
using testing::parse;
using testing::scene_with_shapes;
using testing::shape_area;

/// World position of the point (x, y, z) under `transform` (JSON), through a triangle shape.
glm::dvec3 moved(const glm::dvec3& p, const std::string& transform) {
  char vertices[256];
  std::snprintf(vertices, sizeof vertices, "[[%.17g,%.17g,%.17g],[7,0,0],[7,1,0]]", p.x, p.y, p.z);
  Scene scene = parse(scene_with_shapes(
      std::string(
          R"({"type": "triangles", "material": "white", "indices": [[0,1,2]], "vertices": )") +
      vertices + R"(, "transform": )" + transform + "}"));
  return scene.shapes.at(0).positions.at(0);
}

TEST(Transform, EachKind) {
  expect_near(moved({1, 2, 3}, R"({"scale": 2})"), {2, 4, 6});
  expect_near(moved({1, 2, 3}, R"({"scale": [1, -1, 0.5]})"), {1, -2, 1.5});
  expect_near(moved({1, 2, 3}, R"({"translate": [1, 1, 1]})"), {2, 3, 4});
  // Right-handed: +90 degrees about z turns x into y.
  expect_near(moved({1, 0, 0}, R"({"rotate": {"axis": [0, 0, 1], "angle": 90}})"), {0, 1, 0});
  expect_near(moved({0, 1, 0}, R"({"rotate": {"axis": [2, 0, 0], "angle": 90}})"), {0, 0, 1});
  expect_near(moved({1, 2, 3}, R"({})"), {1, 2, 3});
}

TEST(Transform, ObjectAppliesScaleThenRotateThenTranslate) {
  std::string t =
      R"({"translate": [1, 0, 0], "rotate": {"axis": [0, 0, 1], "angle": 90}, "scale": 2})";
  expect_near(moved({1, 0, 0}, t),
              {1, 2, 0});  // (2,0,0) -> (0,2,0) -> (1,2,0), whatever the key order
}

TEST(Transform, ArrayAppliesFirstElementFirst) {
  expect_near(moved({1, 0, 0}, R"([{"translate": [1, 0, 0]}, {"scale": 2}])"), {4, 0, 0});
  expect_near(moved({1, 0, 0}, R"([{"scale": 2}, {"translate": [1, 0, 0]}])"), {3, 0, 0});
  expect_near(
      moved({1, 0, 0}, R"([{"rotate": {"axis": [0,0,1], "angle": 90}}, {"translate": [0, 0, 5]}])"),
      {0, 1, 5});
}

TEST(Transform, MatrixIsRowMajorAffine) {
  expect_near(moved({1, 2, 3}, R"({"matrix": [[1,0,0,5],[0,1,0,6],[0,0,1,7],[0,0,0,1]]})"),
              {6, 8, 10});
  expect_near(moved({1, 0, 0}, R"({"matrix": [[0,-1,0,0],[1,0,0,0],[0,0,1,0],[0,0,0,1]]})"),
              {0, 1, 0});
  EXPECT_EQ(error_of(scene_with_shapes(R"({"type": "sphere", "material": "white",
                "transform": {"matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,1,1]]}})")),
            "shapes[0].transform.matrix[3]: must be [0, 0, 0, 1] (the transform must be affine)");
  EXPECT_EQ(error_of(scene_with_shapes(R"({"type": "sphere", "material": "white",
                "transform": {"matrix": [[1,0,0,0],[0,1,0,0],[1,1,0,0],[0,0,0,1]]}})")),
            "shapes[0].transform.matrix: must be invertible (its 3x3 part is singular)");
  EXPECT_EQ(error_of(scene_with_shapes(R"({"type": "sphere", "material": "white",
                "transform": {"matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]], "scale": 2}})")),
            "shapes[0].transform.matrix: cannot be combined with scale, rotate or translate in one "
            "object (use an array of transforms)");
  EXPECT_EQ(error_of(scene_with_shapes(R"({"type": "sphere", "material": "white",
                "transform": {"matrix": [[1,0,0],[0,1,0],[0,0,1]]}})")),
            "shapes[0].transform.matrix: must have 4 elements (got 3)");
}

TEST(Transform, BadStepsNameTheirPath) {
  EXPECT_EQ(error_of(scene_with_shapes(
                R"({"type": "sphere", "material": "white", "transform": {"scale": [1, 0, 1]}})")),
            "shapes[0].transform.scale[1]: must be non-zero");
  EXPECT_EQ(
      error_of(scene_with_shapes(
          R"({"type": "sphere", "material": "white", "transform": [{}, {"rotate": {"axis": [0,1,0]}}]})")),
      "shapes[0].transform[1].rotate.angle: required");
  EXPECT_EQ(
      error_of(scene_with_shapes(
          R"({"type": "sphere", "material": "white", "transform": {"rotate": {"axis": [0,0,0], "angle": 3}}})")),
      "shapes[0].transform.rotate.axis: must be a non-zero vector");
  EXPECT_EQ(
      error_of(scene_with_shapes(
          R"({"type": "sphere", "material": "white", "transform": {"shear": 1}})")),
      "shapes[0].transform.shear: unknown key (a transform has: scale, rotate, translate, matrix)");
}

TEST(Transform, MirrorKeepsTheFrontAndNormalsAgree) {
  // Quad at z = 1 facing +z (away from the origin); mirrored through z = 0 it must face -z
  // (still away from the origin), and its shading normals must agree with its winding.
  Scene scene = parse(scene_with_shapes(R"({"type": "triangles", "material": "white",
      "vertices": [[-1,-1,1],[1,-1,1],[1,1,1]], "indices": [[0,1,2]],
      "normals": [[0,0,1],[0,0,1],[0,0,1]], "transform": {"scale": [1, 1, -1]}})"));
  const Shape& shape = scene.shapes[0];
  expect_near(shape.positions[0], {-1, -1, -1});
  expect_near(face_normal(shape, 0), {0, 0, -1});
  expect_near(shape.normals[0], {0, 0, -1});
  // A mirrored box still faces out of itself.
  Shape box = parse(scene_with_shapes(R"({"type": "box", "material": "white",
      "transform": {"matrix": [[-1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}})"))
                  .shapes[0];
  for (size_t t = 0; t < box.indices.size(); ++t) {
    glm::dvec3 c = (box.positions[box.indices[t].x] + box.positions[box.indices[t].y] +
                    box.positions[box.indices[t].z]) /
                   3.0;
    EXPECT_GT(glm::dot(face_normal(box, t), c), 0) << t;
  }
}

TEST(Transform, NormalsUseTheInverseTranspose) {
  // Triangle in the plane x + y = 1 with normals along (1, 1, 0); stretched 2x along x the
  // plane becomes x/2 + y = 1, whose normal is along (1, 2, 0).
  Scene scene = parse(scene_with_shapes(R"({"type": "triangles", "material": "white",
      "vertices": [[1,0,0],[0,1,0],[0,1,1]], "indices": [[0,1,2]],
      "normals": [[1,1,0],[1,1,0],[1,1,0]], "transform": {"scale": [2, 1, 1]}})"));
  const Shape& shape = scene.shapes[0];
  glm::dvec3 expected = glm::normalize(glm::dvec3(1, 2, 0));
  expect_near(shape.normals[0], expected);
  expect_near(face_normal(shape, 0), expected);
}

TEST(Transform, SphereTakesOnlySimilarities) {
  Shape sphere = parse(scene_with_shapes(R"({"type": "sphere", "center": [1, 0, 0], "radius": 0.5,
      "material": "white", "transform": [{"rotate": {"axis": [0,0,1], "angle": 90}}, {"scale": -3},
      {"translate": [0, 0, 1]}]})"))
                     .shapes[0];
  expect_near(sphere.center, {0, -3, 1});
  EXPECT_NEAR(sphere.radius, 1.5, 1e-12);
  EXPECT_FALSE(sphere.flip_normals);  // a mirrored sphere still faces outward
  EXPECT_EQ(error_of(scene_with_shapes(
                R"({"type": "sphere", "material": "white", "transform": {"scale": [1, 2, 1]}})")),
            "shapes[0].transform: a sphere's transform must be a similarity (rotation, uniform "
            "scale, translation)");
}

TEST(Transform, AreaScalesWithTheTransform) {
  Scene scene = parse(scene_with_shapes(
      R"({"type": "box", "material": "white", "transform": {"scale": [2, 3, 4]}})"));
  EXPECT_DOUBLE_EQ(shape_area(scene.shapes[0]), 4 * 2 * (2 * 3 + 3 * 4 + 4 * 2));
}

}  // namespace
}  // namespace tessera
