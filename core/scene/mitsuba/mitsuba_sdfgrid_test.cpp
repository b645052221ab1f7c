// "sdfgrid" shapes read by the Mitsuba importer (inside shapegroups too), and each kind of bad
// grid refused naming the element, file and line.
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "scene/mitsuba/mitsuba_test_support.h"
#include "scene/native/sdfgrid_test_grids.h"

namespace tessera {
namespace {

const std::map<std::string, std::string>& kFiles = testing::kSdfGridFiles;

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
