// "sdfgrid" shapes: the native format (file and inline), the writer's round trip, and each kind
// of bad grid refused naming where it is (the Mitsuba importer's: mitsuba_sdfgrid_test.cpp).
#include "scene/native/sdfgrid_shape.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "scene/native/scene_writer.h"
#include "scene/native/native_test_support.h"
#include "scene/native/sdfgrid_test_grids.h"

namespace tessera {
namespace {

using testing::error_of;
using testing::parse;
using testing::scene_with_shapes;

using testing::sphere_values;

const std::map<std::string, std::string>& kFiles = testing::kSdfGridFiles;

TEST(SdfGridShape, CountsTheVoxelsThatCanHoldTheSurface) {
  EXPECT_EQ(sdf_surface_voxel_count({2, 2, 2}, {1, 1, 1, 1, 1, 1, 1, -1}), 1u);
  EXPECT_EQ(sdf_surface_voxel_count({2, 2, 2}, {1, 1, 1, 1, 1, 1, 1, 0}), 1u);  // a zero corner
  EXPECT_EQ(sdf_surface_voxel_count({2, 2, 2}, std::vector<float>(8, 2)), 0u);
  // The sphere of radius 0.3 on a 5^3 grid (spacing 0.25): the 8 voxels around the centre, and
  // the 24 beside them through a face; the 32 others have all corners outside.
  EXPECT_EQ(sdf_surface_voxel_count({5, 5, 5}, sphere_values(5)), 32u);
}

TEST(SdfGridShape, ReadsAFileWithItsNormalsAndTransform) {
  Scene s = parse(scene_with_shapes(R"({"type": "sdfgrid", "file": "ball.vol", "normals": "analytic",
      "material": "white", "transform": {"scale": 2, "translate": [0, 0, 5]}})"),
                  kFiles);
  ASSERT_EQ(s.shapes.size(), 1u);
  const Shape& shape = s.shapes[0];
  EXPECT_EQ(shape.kind, Shape::Kind::sdfgrid);
  EXPECT_EQ(shape.sdf_normals, SdfNormals::analytic);
  EXPECT_EQ(shape.sdf_resolution, glm::u32vec3(5, 5, 5));
  EXPECT_EQ(shape.sdf_values, sphere_values(5));
  EXPECT_EQ(shape.sdf_file, "ball.vol");
  EXPECT_EQ(shape.to_world[0][0], 2.0);
  EXPECT_EQ(shape.to_world[3], glm::dvec4(0, 0, 5, 1));
  EXPECT_EQ(s.referenced_files, (std::vector<std::string>{"ball.vol"}));
  // The default normals are Mitsuba's: smooth.
  Scene d = parse(scene_with_shapes(R"({"type": "sdfgrid", "file": "ball.vol", "material": "white"})"), kFiles);
  EXPECT_EQ(d.shapes[0].sdf_normals, SdfNormals::smooth);
}

TEST(SdfGridShape, WriterRoundTripsFileAndInlineGrids) {
  Scene s = parse(scene_with_shapes(R"({"type": "sdfgrid", "file": "ball.vol", "normals": "analytic",
      "material": "white", "transform": {"rotate": {"axis": [0, 0, 1], "angle": 30}}})"),
                  kFiles);
  const std::string json = write_scene_json(s);
  EXPECT_NE(json.find("\"file\": \"ball.vol\""), std::string::npos) << json;
  Scene back = parse(json, kFiles);
  ASSERT_EQ(back.shapes.size(), 1u);
  EXPECT_EQ(back.shapes[0].kind, Shape::Kind::sdfgrid);
  EXPECT_EQ(back.shapes[0].sdf_values, s.shapes[0].sdf_values);
  EXPECT_EQ(back.shapes[0].to_world, s.shapes[0].to_world);
  EXPECT_EQ(back.shapes[0].sdf_normals, SdfNormals::analytic);
  EXPECT_EQ(write_scene_json(back), json);

  // Without a file the values are written inline, every float exactly.
  Shape inline_shape = s.shapes[0];
  inline_shape.sdf_file.clear();
  inline_shape.sdf_values[0] = 1e-30f;
  inline_shape.sdf_values[1] = -3.4e38f;
  s.shapes[0] = inline_shape;
  Scene again = parse(write_scene_json(s));
  EXPECT_EQ(again.shapes[0].sdf_values, inline_shape.sdf_values);
  EXPECT_EQ(again.shapes[0].sdf_resolution, glm::u32vec3(5, 5, 5));
  EXPECT_TRUE(again.shapes[0].sdf_file.empty());
}

TEST(SdfGridShape, ErrorsNameThePathAndTheFile) {
  auto shape_error = [&](const std::string& shape) { return error_of(scene_with_shapes(shape), kFiles); };
  EXPECT_EQ(shape_error(R"({"type": "sdfgrid", "file": "none.vol", "material": "white"})"),
            "shapes[0].file: none.vol: no such file in the scene's folder");
  EXPECT_EQ(shape_error(R"({"type": "sdfgrid", "file": "two.vol", "material": "white"})"),
            "shapes[0].file: two.vol: an SDF grid has 1 channel, this file has 2");
  EXPECT_EQ(shape_error(R"({"type": "sdfgrid", "file": "flat.vol", "material": "white"})"),
            "shapes[0].file: flat.vol: an SDF grid needs at least 2 samples along each axis (got 1 x 4 x 4)");
  EXPECT_NE(shape_error(R"({"type": "sdfgrid", "file": "solid.vol", "material": "white"})")
                .find("shapes[0].file: solid.vol: no voxel of the SDF grid holds the surface"),
            std::string::npos);
  EXPECT_EQ(shape_error(R"({"type": "sdfgrid", "file": "ball.vol", "normals": "flat", "material": "white"})"),
            "shapes[0].normals: unknown normals \"flat\" (expected smooth or analytic)");
  EXPECT_EQ(shape_error(R"({"type": "sdfgrid", "file": "ball.vol"})"),
            "shapes[0].material: required (SDF grids cannot emit light)");
  EXPECT_NE(shape_error(R"({"type": "sdfgrid", "file": "ball.vol", "material": "white", "emission": [1, 1, 1]})")
                .find("shapes[0]"),
            std::string::npos);
  EXPECT_EQ(shape_error(R"({"type": "sdfgrid", "file": "ball.vol", "material": "white",
      "transform": {"scale": [1, 0, 1]}})"),
            "shapes[0].transform.scale[1]: must be non-zero");
  EXPECT_EQ(shape_error(R"({"type": "sdfgrid", "resolution": [2, 2, 2], "values": [1, 1, 1, 1, 1, 1, 1],
      "material": "white"})"),
            "shapes[0].values: 7 values for a grid of 2 x 2 x 2");
  EXPECT_EQ(shape_error(R"({"type": "sdfgrid", "resolution": [2, 2, 2], "values": [1, 1, 1, 1, 1, 1, 1, 1e39],
      "material": "white"})"),
            "shapes[0].values[7]: a value must be finite as a 32-bit float (got 1e+39)");
  EXPECT_EQ(shape_error(R"({"type": "sdfgrid", "resolution": [2, 1, 2], "values": [1, -1, 1, 1],
      "material": "white"})"),
            "shapes[0].resolution[1]: must be in [2, 1048576] (got 1)");
}

}  // namespace
}  // namespace tessera
