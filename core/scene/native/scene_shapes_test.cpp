// Scene format v1: every shape type parses to the documented world-space geometry.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "scene/native/native_test_support.h"

namespace tessera {
namespace {

using testing::error_of;
using testing::expect_near;
using testing::face_center;
using testing::face_normal;
using testing::parse;
using testing::scene_with_shapes;
using testing::shape_area;

constexpr double kPi = std::numbers::pi;
const char* kQuadZ = R"("vertices": [[-1,-1,0],[1,-1,0],[1,1,0],[-1,1,0]])";  // front: +z

Shape only_shape(const std::string& shape_json) {
  Scene scene = parse(scene_with_shapes(shape_json));
  EXPECT_EQ(scene.shapes.size(), 1u);
  return scene.shapes.at(0);
}

/// Every triangle's front faces away from `inside` (or toward it when `inward`).
void expect_facing(const Shape& shape, const glm::dvec3& inside, bool inward) {
  for (size_t t = 0; t < shape.indices.size(); ++t) {
    double d = glm::dot(face_normal(shape, t), face_center(shape, t) - inside);
    if (inward) {
      EXPECT_LT(d, 0) << "triangle " << t;
    } else {
      EXPECT_GT(d, 0) << "triangle " << t;
    }
  }
}

TEST(SceneShapes, QuadIsTwoTrianglesFacingItsCounterClockwiseSide) {
  Shape quad = only_shape(std::string(R"({"type": "quad", "material": "white", )") + kQuadZ + "}");
  EXPECT_EQ(quad.kind, Shape::Kind::triangles);
  ASSERT_EQ(quad.indices.size(), 2u);
  EXPECT_EQ(quad.indices[0], glm::u32vec3(0, 1, 2));
  EXPECT_EQ(quad.indices[1], glm::u32vec3(0, 2, 3));
  EXPECT_DOUBLE_EQ(shape_area(quad), 4.0);
  expect_near(face_normal(quad, 0), {0, 0, 1});
  expect_near(face_normal(quad, 1), {0, 0, 1});
  EXPECT_TRUE(quad.normals.empty());
  EXPECT_FALSE(quad.is_emitter());
}

TEST(SceneShapes, QuadMustBePlanarConvexAndNonDegenerate) {
  EXPECT_EQ(
      error_of(scene_with_shapes(
          R"({"type": "quad", "material": "white", "vertices": [[0,0,0],[1,0,0],[1,1,0.01],[0,1,0]]})")),
      "shapes[0].vertices: quad is not planar (a vertex is 0.0025 off its plane; the "
      "tolerance is 1e-5 of its size)");
  // 1e-7 off the plane of a unit quad is within tolerance.
  EXPECT_EQ(
      only_shape(
          R"({"type": "quad", "material": "white", "vertices": [[0,0,0],[1,0,0],[1,1,1e-7],[0,1,0]]})")
          .indices.size(),
      2u);
  EXPECT_EQ(
      error_of(scene_with_shapes(
          R"({"type": "quad", "material": "white", "vertices": [[0,0,0],[1,0,0],[2,0,0],[3,0,0]]})")),
      "shapes[0].vertices: quad is degenerate (zero area, or three of its vertices on one "
      "line)");
  EXPECT_EQ(
      error_of(scene_with_shapes(
          R"({"type": "quad", "material": "white", "vertices": [[0,0,0],[1,0,0],[0,1,0],[1,1,0]]})")),
      "shapes[0].vertices: quad is not convex, or its vertices are not in order around it");
  EXPECT_EQ(error_of(scene_with_shapes(
                R"({"type": "quad", "material": "white", "vertices": [[0,0,0],[1,0,0],[1,1,0]]})")),
            "shapes[0].vertices: must have 4 elements (got 3)");
}

TEST(SceneShapes, SphereKeepsCenterAndRadius) {
  Shape sphere =
      only_shape(R"({"type": "sphere", "center": [1, 2, 3], "radius": 0.5, "material": "white"})");
  EXPECT_EQ(sphere.kind, Shape::Kind::sphere);
  EXPECT_EQ(sphere.center, glm::dvec3(1, 2, 3));
  EXPECT_EQ(sphere.radius, 0.5);
  EXPECT_FALSE(sphere.flip_normals);
  Shape unit = only_shape(R"({"type": "sphere", "material": "white", "flip_normals": true})");
  EXPECT_EQ(unit.center, glm::dvec3(0));
  EXPECT_EQ(unit.radius, 1);
  EXPECT_TRUE(unit.flip_normals);  // faces inward
}

TEST(SceneShapes, TrianglesKeepIndicesNormalsAndArea) {
  Shape shape = only_shape(R"({"type": "triangles", "material": "white",
      "vertices": [[0,0,0],[2,0,0],[0,2,0],[0,0,2]],
      "indices": [[0,1,2],[0,3,1]],
      "normals": [[0,0,1],[0,0,1],[0,0,1],[0,0,1]]})");
  ASSERT_EQ(shape.indices.size(), 2u);
  EXPECT_DOUBLE_EQ(shape_area(shape), 4.0);
  expect_near(face_normal(shape, 0), {0, 0, 1});
  expect_near(face_normal(shape, 1), {0, 1, 0});
  ASSERT_EQ(shape.normals.size(), 4u);
  expect_near(shape.normals[0], {0, 0, 1});
}

TEST(SceneShapes, FlipNormalsReversesWindingAndNormals) {
  Shape shape = only_shape(R"({"type": "triangles", "material": "white", "flip_normals": true,
      "vertices": [[0,0,0],[1,0,0],[0,1,0]], "indices": [[0,1,2]], "normals": [[0,0,2],[0,0,1],[0,0,1]]})");
  EXPECT_TRUE(shape.flip_normals);
  EXPECT_EQ(shape.indices[0], glm::u32vec3(0, 2, 1));
  expect_near(face_normal(shape, 0), {0, 0, -1});
  expect_near(shape.normals[0], {0, 0, -1});  // unit length after the (identity) transform
  Shape quad =
      only_shape(std::string(R"({"type": "quad", "material": "white", "flip_normals": true, )") +
                 kQuadZ + "}");
  expect_near(face_normal(quad, 0), {0, 0, -1});
}

TEST(SceneShapes, BoxFacesOutwardAndInwardWhenFlipped) {
  Shape box =
      only_shape(R"({"type": "box", "min": [0, 0, 0], "max": [1, 2, 3], "material": "white"})");
  ASSERT_EQ(box.indices.size(), 12u);
  EXPECT_DOUBLE_EQ(shape_area(box), 2 * (1 * 2 + 2 * 3 + 3 * 1));
  expect_facing(box, {0.5, 1, 1.5}, /*inward=*/false);
  for (size_t t = 0; t < 12; ++t) {  // every normal is an axis
    glm::dvec3 n = face_normal(box, t);
    EXPECT_NEAR(std::abs(n.x) + std::abs(n.y) + std::abs(n.z), 1.0, 1e-12);
  }
  Shape room = only_shape(
      R"({"type": "box", "min": [0, 0, 0], "max": [1, 2, 3], "material": "white", "flip_normals": true})");
  expect_facing(room, {0.5, 1, 1.5}, /*inward=*/true);
  Shape cube = only_shape(R"({"type": "box", "material": "white"})");  // default [-1, 1]^3
  EXPECT_DOUBLE_EQ(shape_area(cube), 24.0);
  EXPECT_EQ(error_of(scene_with_shapes(
                R"({"type": "box", "min": [0,0,0], "max": [1,0,1], "material": "white"})")),
            "shapes[0].max[1]: must be > min[1] (got 0 <= 0)");
}

TEST(SceneShapes, TetrahedronFacesOutwardWhateverTheVertexOrder) {
  const char* orders[] = {"[[0,0,0],[1,0,0],[0,1,0],[0,0,1]]", "[[1,0,0],[0,0,0],[0,1,0],[0,0,1]]",
                          "[[0,0,1],[0,1,0],[1,0,0],[0,0,0]]"};
  for (const char* vertices : orders) {
    Shape tet =
        only_shape(std::string(R"({"type": "tetrahedron", "material": "white", "vertices": )") +
                   vertices + "}");
    ASSERT_EQ(tet.indices.size(), 4u);
    expect_facing(tet, {0.25, 0.25, 0.25}, /*inward=*/false);
    EXPECT_NEAR(shape_area(tet), 1.5 + std::sqrt(3.0) / 2, 1e-12);
  }
  EXPECT_EQ(
      error_of(scene_with_shapes(
          R"({"type": "tetrahedron", "material": "white", "vertices": [[0,0,0],[1,0,0],[0,1,0],[1,1,0]]})")),
      "shapes[0].vertices: tetrahedron is flat (its 4 vertices are in one plane)");
}

TEST(SceneShapes, PowerBecomesRadianceOverWorldArea) {
  // A 2x2 quad (area 4) emitting 4*pi W: radiance 1 one-sided, 1/2 two-sided.
  Scene scene = parse(scene_with_shapes(
      std::string(
          R"({"type": "quad", "material": "white", "power": [12.566370614359172, 0, 6.283185307179586], )") +
      kQuadZ + "}, " + R"({"type": "quad", "power": 12.566370614359172, "two_sided": true, )" +
      kQuadZ + "}, " +
      R"({"type": "quad", "power": 12.566370614359172, "transform": {"scale": 2}, )" + kQuadZ +
      "}"));
  expect_near(scene.shapes[0].emission, {1, 0, 0.5}, 1e-12);
  EXPECT_FALSE(scene.shapes[0].two_sided_emission);
  expect_near(scene.shapes[1].emission, {0.5, 0.5, 0.5}, 1e-12);
  EXPECT_TRUE(scene.shapes[1].two_sided_emission);
  EXPECT_EQ(scene.materials[scene.shapes[1].material].name, "(black) (two-sided)");
  expect_near(scene.shapes[2].emission, {0.25, 0.25, 0.25}, 1e-12);  // area 16 after scaling
}

TEST(SceneShapes, SpherePowerUsesItsSurfaceArea) {
  Shape sphere =
      only_shape(R"({"type": "sphere", "radius": 0.5, "power": 100, "transform": {"scale": 2}})");
  double area = 4 * kPi * 1.0 * 1.0;  // radius 1 after the transform
  expect_near(sphere.emission, glm::dvec3(100 / (kPi * area)), 1e-12);
}

TEST(SceneShapes, EmissionIsRadianceAsGiven) {
  Shape light = only_shape(R"({"type": "sphere", "emission": [17, 12, 4], "two_sided": true})");
  EXPECT_EQ(light.emission, glm::dvec3(17, 12, 4));
  EXPECT_TRUE(light.two_sided_emission);
  EXPECT_EQ(error_of(scene_with_shapes(R"({"type": "sphere", "emission": [1,1,1], "power": 3})")),
            "shapes[0].power: give either emission or power, not both");
  EXPECT_EQ(error_of(scene_with_shapes(R"({"type": "sphere", "emission": [1,-1,1]})")),
            "shapes[0].emission[1]: must be >= 0 (got -1)");
  EXPECT_EQ(error_of(scene_with_shapes(R"({"type": "sphere", "power": -3})")),
            "shapes[0].power: must be >= 0 (got -3)");
}

TEST(SceneShapes, UnknownShapeTypeAndForeignKeys) {
  EXPECT_EQ(error_of(scene_with_shapes(R"({"type": "cone", "material": "white"})")),
            "shapes[0].type: unknown shape type \"cone\" (expected quad, sphere, triangles, box, "
            "tetrahedron, mesh, curves, sdfgrid or instance)");
  EXPECT_EQ(error_of(scene_with_shapes(R"({"type": "quad", "radius": 1, "material": "white"})")),
            "shapes[0].radius: unknown key (a \"quad\" shape has: type, material, emission, power, "
            "two_sided, flip_normals, transform, interior, exterior, vertices)");
  EXPECT_EQ(error_of(scene_with_shapes(R"({"material": "white"})")), "shapes[0].type: required");
}

}  // namespace
}  // namespace tessera
