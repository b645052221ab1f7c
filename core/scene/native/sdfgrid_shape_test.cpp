// "sdfgrid" shapes: the native format (file and inline), the writer's round trip, the Mitsuba
// importer (inside shapegroups too), and each kind of bad grid refused naming where it is.
#include "scene/native/sdfgrid_shape.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "scene/mitsuba/mitsuba_test_support.h"
#include "scene/native/scene_writer.h"
#include "scene/scene_test_support.h"

namespace tessera {
namespace {

using testing::error_of;
using testing::parse;
using testing::scene_with_shapes;

/// A Mitsuba .vol file (version 3, float32) of the given grid.
std::string vol_file(uint32_t nx, uint32_t ny, uint32_t nz, uint32_t channels, const std::vector<float>& values) {
  std::string out = "VOL";
  out.push_back(char(3));
  auto put = [&](const void* p, size_t n) { out.append(static_cast<const char*>(p), n); };
  const int32_t header[5] = {1, int32_t(nx), int32_t(ny), int32_t(nz), int32_t(channels)};
  put(header, sizeof(header));
  const float box[6] = {0, 0, 0, 1, 1, 1};
  put(box, sizeof(box));
  put(values.data(), values.size() * sizeof(float));
  return out;
}

/// Distance to a sphere of radius 0.3 around (0.5, 0.5, 0.5), sampled on n^3 points of [0, 1]^3.
std::vector<float> sphere_values(uint32_t n) {
  std::vector<float> v;
  for (uint32_t z = 0; z < n; ++z) {
    for (uint32_t y = 0; y < n; ++y) {
      for (uint32_t x = 0; x < n; ++x) {
        const glm::dvec3 p = glm::dvec3(x, y, z) / double(n - 1);
        v.push_back(float(glm::length(p - glm::dvec3(0.5)) - 0.3));
      }
    }
  }
  return v;
}

const std::map<std::string, std::string> kFiles = {
    {"ball.vol", vol_file(5, 5, 5, 1, sphere_values(5))},
    {"two.vol", vol_file(2, 2, 2, 2, std::vector<float>(16, -1.0f))},
    {"flat.vol", vol_file(1, 4, 4, 1, std::vector<float>(16, -1.0f))},
    {"solid.vol", vol_file(3, 3, 3, 1, std::vector<float>(27, 0.5f))},
};

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

using testing::mitsuba_scene;
using testing::parse_xml;
using testing::xml_error;
using testing::line_of;

TEST(SdfGridShape, MitsubaSdfgridInAShapegroup) {
  Scene s = parse_xml(mitsuba_scene(R"(
    <shape type="shapegroup" id="g"><shape type="sdfgrid">
      <string name="filename" value="ball.vol"/><string name="normals" value="analytic"/>
      <transform name="to_world"><scale value="3"/></transform></shape></shape>
    <shape type="instance"><ref id="g"/></shape>
    <shape type="sdfgrid"><string name="filename" value="ball.vol"/></shape>)"),
                      kFiles);
  ASSERT_EQ(s.groups.size(), 1u);
  ASSERT_EQ(s.groups[0].shapes.size(), 1u);
  const Shape& in_group = s.groups[0].shapes[0];
  EXPECT_EQ(in_group.kind, Shape::Kind::sdfgrid);
  EXPECT_EQ(in_group.sdf_normals, SdfNormals::analytic);
  EXPECT_EQ(in_group.to_world[1][1], 3.0);
  ASSERT_EQ(s.shapes.size(), 2u);
  EXPECT_EQ(s.shapes[1].kind, Shape::Kind::sdfgrid);
  EXPECT_EQ(s.shapes[1].sdf_normals, SdfNormals::smooth);
  EXPECT_EQ(s.referenced_files, (std::vector<std::string>{"ball.vol"}));
}

TEST(SdfGridShape, MitsubaErrorsNameTheElementFileAndLine) {
  auto grid = [](const std::string& inside) {
    return mitsuba_scene("<shape type=\"sdfgrid\">\n" + inside + "\n</shape>");
  };
  const std::string missing = grid(R"(<string name="filename" value="none.vol"/>)");
  std::string e = xml_error(missing, kFiles);
  EXPECT_NE(e.find("line " + std::to_string(line_of(missing, "none.vol"))), std::string::npos) << e;
  EXPECT_NE(e.find("none.vol"), std::string::npos) << e;
  const std::string solid = grid(R"(<string name="filename" value="solid.vol"/>)");
  e = xml_error(solid, kFiles);
  EXPECT_NE(e.find("line " + std::to_string(line_of(solid, "solid.vol"))), std::string::npos) << e;
  EXPECT_NE(e.find("solid.vol: no voxel of the SDF grid holds the surface"), std::string::npos) << e;
  e = xml_error(grid(R"(<string name="filename" value="two.vol"/>)"), kFiles);
  EXPECT_NE(e.find("two.vol: an SDF grid has 1 channel, this file has 2"), std::string::npos) << e;
  e = xml_error(grid(R"(<string name="filename" value="flat.vol"/>)"), kFiles);
  EXPECT_NE(e.find("at least 2 samples along each axis"), std::string::npos) << e;
  e = xml_error(grid(R"(<string name="filename" value="ball.vol"/><boolean name="flip_normals" value="true"/>)"),
                kFiles);
  EXPECT_NE(e.find("an sdfgrid has no flip_normals"), std::string::npos) << e;
  e = xml_error(grid(R"(<string name="filename" value="ball.vol"/><emitter type="area"/>)"), kFiles);
  EXPECT_NE(e.find("an sdfgrid cannot emit light"), std::string::npos) << e;
  e = xml_error(grid(R"(<string name="filename" value="ball.vol"/><string name="normals" value="flat"/>)"),
                kFiles);
  EXPECT_NE(e.find("unknown normals \"flat\" (expected smooth or analytic)"), std::string::npos) << e;
  e = xml_error(grid(R"(<string name="normals" value="smooth"/>)"), kFiles);
  EXPECT_NE(e.find("missing <string name=\"filename\">"), std::string::npos) << e;
}

TEST(SdfGridShape, MitsubaClipPlanesThatCouldHideAGridAreRefused) {
  // The camera at (0, 0, 5) looks down -z; the grid's box spans z in [0, 1].
  const std::string sensor = R"(<sensor type="perspective">
    <float name="fov" value="40"/><float name="near_clip" value="4.5"/>
    <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="64"/><integer name="height" value="48"/>
      <rfilter type="box"/></film></sensor>
)";
  const std::string grid = R"(<shape type="sdfgrid"><string name="filename" value="ball.vol"/></shape>)";
  EXPECT_NE(xml_error(mitsuba_scene(grid, sensor), kFiles).find("near_clip 4.5 could hide part of"),
            std::string::npos);
  EXPECT_EQ(xml_error(mitsuba_scene(grid), kFiles), "(no error)");
}

}  // namespace
}  // namespace tessera
