// Mitsuba shapes: built-in geometry, spheres, mesh files, normals, flip_normals, area emitters.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <glm/geometric.hpp>
#include <numbers>
#include <random>

#include "scene/mitsuba/mitsuba_shape_geometry.h"
#include "scene/mitsuba/mitsuba_test_support.h"
#include "scene/mitsuba/mitsuba_vertex_normals.h"

namespace tessera {
namespace {

using testing::expect_near;
using testing::face_center;
using testing::face_normal;
using testing::kSourceDir;
using testing::line_of;
using testing::mitsuba_scene;
using testing::parse_xml;
using testing::shape_area;
using testing::xml_error;

Shape shape_of(const std::string& shape, std::map<std::string, std::string> files = {}) {
  return parse_xml(mitsuba_scene(shape), std::move(files)).shapes.at(0);
}

/// A tiny ASCII PLY: a square pyramid's four sides without its base, apex up.
const char* kPyramidPly = R"(ply
format ascii 1.0
element vertex 5
property float x
property float y
property float z
element face 4
property list uchar int vertex_indices
end_header
0 0 1
-1 -1 0
1 -1 0
1 1 0
-1 1 0
3 0 1 2
3 0 2 3
3 0 3 4
3 0 4 1
)";

TEST(MitsubaShape, RectangleIsTheSquareFacingPlusZ) {
  Shape s = shape_of(R"(<shape type="rectangle"/>)");
  EXPECT_EQ(s.kind, Shape::Kind::triangles);
  EXPECT_EQ(s.indices.size(), 2u);
  for (const glm::dvec3& p : s.positions) {
    EXPECT_EQ(std::abs(p.x), 1);
    EXPECT_EQ(std::abs(p.y), 1);
    EXPECT_EQ(p.z, 0);
  }
  for (size_t t = 0; t < 2; ++t) expect_near(face_normal(s, t), {0, 0, 1});
  EXPECT_DOUBLE_EQ(shape_area(s), 4);
  EXPECT_TRUE(s.normals.empty());
}

TEST(MitsubaShape, CubeFacesOutward) {
  Shape s = shape_of(R"(<shape type="cube"/>)");
  EXPECT_EQ(s.indices.size(), 12u);
  EXPECT_DOUBLE_EQ(shape_area(s), 24);
  for (size_t t = 0; t < 12; ++t) {
    glm::dvec3 n = face_normal(s, t), c = face_center(s, t);
    EXPECT_NEAR(glm::dot(n, c), 1, 1e-12);  // each face's normal is its outward axis
  }
}

TEST(MitsubaShape, DiskIsATessellatedUnitDiskFacingPlusZ) {
  Shape s = shape_of(R"(<shape type="disk"/>)");
  EXPECT_EQ(s.indices.size(), size_t(kMitsubaDiskSegments));
  for (size_t t = 0; t < s.indices.size(); ++t) expect_near(face_normal(s, t), {0, 0, 1});
  double n = kMitsubaDiskSegments;
  EXPECT_NEAR(shape_area(s), n / 2 * std::sin(2 * std::numbers::pi / n), 1e-12);
  EXPECT_GT(shape_area(s), 0.9998 * std::numbers::pi);
  for (const glm::dvec3& p : s.positions) EXPECT_LE(glm::length(p), 1 + 1e-15);
}

TEST(MitsubaShape, ToWorldAndFlipNormals) {
  Shape s = shape_of(R"(<shape type="rectangle"><transform name="to_world">
      <scale value="2"/><rotate x="1" angle="-90"/><translate y="3"/></transform></shape>)");
  for (size_t t = 0; t < 2; ++t) expect_near(face_normal(s, t), {0, 1, 0}, 1e-15);
  for (const glm::dvec3& p : s.positions) EXPECT_NEAR(p.y, 3, 1e-15);
  EXPECT_NEAR(shape_area(s), 16, 1e-12);
  Shape flipped = shape_of(R"(<shape type="rectangle"><boolean name="flip_normals" value="true"/>
      </shape>)");
  for (size_t t = 0; t < 2; ++t) expect_near(face_normal(flipped, t), {0, 0, -1});
  // A mirror keeps the front the front, as in Mitsuba.
  Shape mirrored = shape_of(R"(<shape type="rectangle"><transform name="to_world">
      <scale x="-1"/></transform></shape>)");
  for (size_t t = 0; t < 2; ++t) expect_near(face_normal(mirrored, t), {0, 0, 1});
}

TEST(MitsubaShape, SpheresStayExact) {
  Shape s = shape_of(R"(<shape type="sphere"><point name="center" x="1" y="2" z="3"/>
      <float name="radius" value="0.5"/><transform name="to_world"><scale value="2"/>
      <translate x="1"/></transform></shape>)");
  EXPECT_EQ(s.kind, Shape::Kind::sphere);
  expect_near(s.center, {3, 4, 6});
  EXPECT_DOUBLE_EQ(s.radius, 1);
  EXPECT_FALSE(s.flip_normals);
  Shape unit = shape_of(R"(<shape type="sphere"/>)");
  EXPECT_EQ(unit.center, glm::dvec3(0));
  EXPECT_EQ(unit.radius, 1);
  EXPECT_TRUE(shape_of(R"(<shape type="sphere"><boolean name="flip_normals" value="true"/>
      </shape>)")
                  .flip_normals);
  EXPECT_EQ(
      shape_of(R"(<shape type="sphere"><point name="center" value="1, 2, 3"/></shape>)").center,
      glm::dvec3(1, 2, 3));
}

TEST(MitsubaShape, SphereLimits) {
  EXPECT_NE(xml_error(mitsuba_scene(R"(<shape type="sphere"><transform name="to_world">
      <scale x="2"/></transform></shape>)"))
                .find("a sphere's to_world must be a similarity"),
            std::string::npos);
  EXPECT_NE(xml_error(mitsuba_scene(R"(<shape type="sphere"><float name="radius" value="0"/>
      </shape>)"))
                .find("<float name=\"radius\">: must be > 0 (got 0)"),
            std::string::npos);
  EXPECT_NE(xml_error(mitsuba_scene(R"(<shape type="sphere"><boolean name="face_normals"
      value="true"/></shape>)"))
                .find("is not supported in <shape type=\"sphere\">"),
            std::string::npos);
}

TEST(MitsubaShape, PlyWithoutNormalsGetsMitsubasVertexNormals) {
  Shape s = shape_of(R"(<shape type="ply"><string name="filename" value="pyramid.ply"/></shape>)",
                     {{"pyramid.ply", kPyramidPly}});
  ASSERT_EQ(s.normals.size(), 5u);
  expect_near(s.normals[0], {0, 0, 1}, 1e-15);  // the apex: four sides cancel sideways
  // A base corner: two sides, normals (0, -1, 1) and (-1, 0, 1) over root 2, equal angles.
  expect_near(s.normals[1], glm::normalize(glm::dvec3(-1, -1, 2)), 1e-15);
  for (const glm::dvec3& n : s.normals) EXPECT_EQ(glm::normalize(n), n);  // stable
  Shape flat = shape_of(R"(<shape type="ply"><string name="filename" value="pyramid.ply"/>
      <boolean name="face_normals" value="true"/></shape>)",
                        {{"pyramid.ply", kPyramidPly}});
  EXPECT_TRUE(flat.normals.empty());
}

TEST(MitsubaShape, VertexNormalsAreAngleWeighted) {
  // Vertex 0 has a 90 degree corner facing +z and a 45 degree corner facing +x.
  TriangleMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 1, 1}};
  mesh.indices = {{0, 1, 2}, {0, 2, 3}};
  compute_mitsuba_vertex_normals(mesh);
  expect_near(mesh.normals[0], glm::normalize(glm::dvec3(0.25, 0, 0.5)), 1e-15);
  expect_near(mesh.normals[1], {0, 0, 1});
  // A vertex no triangle uses gets Mitsuba's placeholder.
  mesh.positions.push_back({5, 5, 5});
  compute_mitsuba_vertex_normals(mesh);
  EXPECT_EQ(mesh.normals[4], glm::dvec3(1, 0, 0));
}

TEST(MitsubaShape, StableUnitVectorsSurviveRenormalisation) {
  std::mt19937_64 random(3);
  std::normal_distribution<double> gauss;
  for (int i = 0; i < 100000; ++i) {
    glm::dvec3 n = glm::normalize(glm::dvec3(gauss(random), gauss(random), gauss(random)));
    glm::dvec3 w = stable_unit_vector(n);
    ASSERT_EQ(glm::normalize(w), w);
    EXPECT_LE(glm::length(w - n), 1e-14);
  }
}

TEST(MitsubaShape, ObjIsReadWithoutItsMaterials) {
  std::string obj =
      "mtllib missing.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nusemtl red\n"
      "f 1 2 3 4\n";
  Scene s = parse_xml(mitsuba_scene(R"(<shape type="obj"><string name="filename" value="q.obj"/>
      <boolean name="face_normals" value="true"/><boolean name="flip_tex_coords" value="false"/>
      </shape>)"),
                      {{"q.obj", obj}});
  ASSERT_EQ(s.shapes.size(), 1u);
  EXPECT_EQ(s.shapes[0].indices.size(), 2u);
  EXPECT_EQ(s.referenced_files, std::vector<std::string>{"q.obj"});  // no MTL, as in Mitsuba
  EXPECT_EQ(s.materials.at(s.shapes[0].material).name, "(Mitsuba default diffuse)");
}

// The Mitsuba 3 version of Bitterli's staircase has an OBJ (Mesh432.obj) whose two faces both
// repeat a vertex. Mitsuba loads it and no ray hits it: the scene leaves the shape out (with a
// note), also inside a shapegroup. As a light it would have no area, and is refused.
TEST(MitsubaShape, MeshWhoseFacesAreAllDegenerateIsLeftOut) {
  std::string flat = "v 0 0 0\nv 1 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 4 1 1\n";
  std::string good = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  Scene s = parse_xml(mitsuba_scene(R"(
      <shape type="obj"><string name="filename" value="flat.obj"/></shape>
      <shape type="obj"><string name="filename" value="good.obj"/></shape>
      <shape type="shapegroup" id="g"><shape type="obj"><string name="filename" value="flat.obj"/>
        </shape><shape type="cube"/></shape>
      <shape type="instance"><ref id="g"/></shape>)"),
                      {{"flat.obj", flat}, {"good.obj", good}});
  ASSERT_EQ(s.shapes.size(), 2u);
  EXPECT_EQ(s.shapes[0].indices.size(), 1u);
  ASSERT_EQ(s.groups.size(), 1u);
  EXPECT_EQ(s.groups[0].shapes.size(), 1u);  // the cube
  std::string light = mitsuba_scene(R"(<shape type="obj"><string name="filename" value="f.obj"/>
      <emitter type="area"/></shape>)");
  EXPECT_NE(xml_error(light, {{"f.obj", flat}})
                .find("a light must have a positive, finite area (got 0)"),
            std::string::npos)
      << xml_error(light, {{"f.obj", flat}});
}

TEST(MitsubaShape, ObjNormalsFromTheFileAreKept) {
  std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 2\nf 1//1 2//1 3//1\n";
  Shape s = shape_of(R"(<shape type="obj"><string name="filename" value="t.obj"/>
      <transform name="to_world"><rotate x="1" angle="90"/></transform></shape>)",
                     {{"t.obj", obj}});
  ASSERT_EQ(s.normals.size(), 3u);
  expect_near(s.normals[0], {0, -1, 0}, 1e-15);
}

TEST(MitsubaShape, McGuireBoxAndBunnyFromTheScenesFolder) {
  FileReader scenes = folder_reader(kSourceDir + "/scenes");
  Scene box = parse_mitsuba_scene(mitsuba_scene(R"(<shape type="obj">
      <string name="filename" value="mcguire-cornell/CornellBox-Original.obj"/></shape>)"),
                                  "box.xml", scenes);
  EXPECT_EQ(box.shapes.at(0).indices.size(), 36u);
  EXPECT_EQ(box.referenced_files,
            std::vector<std::string>{"mcguire-cornell/CornellBox-Original.obj"});
  Scene bunny = parse_mitsuba_scene(mitsuba_scene(R"(<shape type="ply">
      <string name="filename" value="meshes/bunny.ply"/></shape>)"),
                                    "bunny.xml", scenes);
  const Shape& b = bunny.shapes.at(0);
  EXPECT_EQ(b.indices.size() + b.dropped_triangles, 69451u);
  ASSERT_EQ(b.normals.size(), b.positions.size());
  for (const glm::dvec3& n : b.normals) ASSERT_EQ(glm::normalize(n), n);
}

TEST(MitsubaShape, MeshPathsFollowTheBundleRules) {
  EXPECT_NE(xml_error(mitsuba_scene(R"(<shape type="ply"><string name="filename"
      value="../outside.ply"/></shape>)"))
                .find("<string name=\"filename\">: \"../outside.ply\" leaves the bundle root"),
            std::string::npos);
  EXPECT_NE(xml_error(mitsuba_scene(R"(<shape type="ply"><string name="filename"
      value="/etc/outside.ply"/></shape>)"))
                .find("<string name=\"filename\">: \"/etc/outside.ply\" is absolute"),
            std::string::npos);
  std::string xml = mitsuba_scene(
      "<shape type=\"ply\">\n<string name=\"filename\" "
      "value=\"gone.ply\"/></shape>");
  EXPECT_EQ(xml_error(xml), "test.xml: line " + std::to_string(line_of(xml, "<string")) +
                                ": <string name=\"filename\">: gone.ply: no such file in the "
                                "scene's folder");
  EXPECT_NE(
      xml_error(mitsuba_scene(R"(<shape type="obj"/>)")).find("missing <string name=\"filename\">"),
      std::string::npos);
  EXPECT_NE(xml_error(mitsuba_scene(R"(<shape type="ply"><string name="filename" value="a.stl"/>
      </shape>)"),
                      {{"a.stl", "solid"}})
                .find("a.stl: unsupported mesh format"),
            std::string::npos);
}

TEST(MitsubaShape, MeshPathsInIncludedFilesAreResolvedAsMitsubaDoes) {
  // Mitsuba resolves a plugin's filename after parsing, from the scene's folder and its <path>s,
  // not from the included file's folder.
  Scene s = parse_xml(mitsuba_scene(R"(<include filename="parts/pyramid.xml"/>)"),
                      {{"parts/pyramid.xml", R"(<shape version="3.0.0" type="ply">
                          <string name="filename" value="meshes/pyramid.ply"/></shape>)"},
                       {"meshes/pyramid.ply", kPyramidPly}});
  EXPECT_EQ(s.referenced_files,
            (std::vector<std::string>{"parts/pyramid.xml", "meshes/pyramid.ply"}));
  EXPECT_EQ(s.shapes.at(0).origin, "parts/pyramid.xml: line 1: <shape type=\"ply\">");
  // A <path> is searched before the scene's folder; ".." may reach a shared folder.
  Scene shared = parse_mitsuba_scene(
      mitsuba_scene(R"(<path value="../common"/><shape type="ply">
          <string name="filename" value="pyramid.ply"/></shape>)"),
      "scenes/a/test.xml",
      testing::memory_reader({{"scenes/common/pyramid.ply", kPyramidPly}}));
  EXPECT_EQ(shared.referenced_files, std::vector<std::string>{"scenes/common/pyramid.ply"});
}

TEST(MitsubaShape, BuiltinShapesHaveMitsubasUvs) {
  Shape rectangle = shape_of(R"(<shape type="rectangle"/>)");
  ASSERT_EQ(rectangle.uvs.size(), rectangle.positions.size());
  for (size_t i = 0; i < rectangle.uvs.size(); ++i) {
    EXPECT_EQ(rectangle.uvs[i], glm::dvec2((rectangle.positions[i].x + 1) / 2,
                                           (rectangle.positions[i].y + 1) / 2));
  }
  Shape cube = shape_of(R"(<shape type="cube"/>)");
  EXPECT_EQ(cube.positions.size(), 24u);  // 4 vertices per face, as Mitsuba's cube
  ASSERT_EQ(cube.uvs.size(), 24u);
  EXPECT_EQ(cube.uvs[0], glm::dvec2(0, 1));
  EXPECT_EQ(cube.uvs[2], glm::dvec2(1, 0));
  Shape disk = shape_of(R"(<shape type="disk"/>)");
  ASSERT_EQ(disk.uvs.size(), disk.positions.size());
  for (size_t i = 0; i < disk.uvs.size(); ++i) {
    const glm::dvec3& p = disk.positions[i];
    EXPECT_NEAR(disk.uvs[i].x, glm::length(p), 1e-12);  // u = r
    if (glm::length(p) > 0.5 && disk.uvs[i].y < 1) {
      double phi = std::atan2(p.y, p.x);
      if (phi < 0) phi += 2 * std::numbers::pi;
      EXPECT_NEAR(disk.uvs[i].y, phi / (2 * std::numbers::pi), 1e-12);  // v = phi / 2 pi
    }
  }
  Shape sphere = shape_of(R"(<shape type="sphere"><transform name="to_world">
      <rotate z="1" angle="90"/><scale value="2"/></transform></shape>)");
  testing::expect_near(sphere.frame[0], glm::dvec3(0, 1, 0), 1e-12);  // local x -> world y
  EXPECT_EQ(sphere.radius, 2);
}

TEST(MitsubaShape, CylinderIsMitsubasOpenTube) {
  Shape c = shape_of(R"(<shape type="cylinder"><point name="p0" value="1, 2, 3"/>
      <point name="p1" value="1, 2, 7"/><float name="radius" value="0.5"/></shape>)");
  double n = kMitsubaDiskSegments;
  // The inscribed 256-gon of radius 0.5 (perimeter 2 r n sin(pi / n)) times the length 4.
  EXPECT_NEAR(shape_area(c), 2 * 0.5 * n * std::sin(std::numbers::pi / n) * 4, 1e-9);
  ASSERT_EQ(c.uvs.size(), c.positions.size());
  ASSERT_EQ(c.normals.size(), c.positions.size());
  for (size_t i = 0; i < c.positions.size(); ++i) {
    glm::dvec3 radial = c.positions[i] - glm::dvec3(1, 2, c.positions[i].z);
    EXPECT_NEAR(glm::length(radial), 0.5, 1e-12);
    EXPECT_NEAR(c.uvs[i].y, (c.positions[i].z - 3) / 4, 1e-12);  // v runs from p0 to p1
    testing::expect_near(c.normals[i], radial / 0.5, 1e-12);    // outward, smooth
  }
  for (size_t t = 0; t < c.indices.size(); ++t) {
    glm::dvec3 centre = face_center(c, t);
    EXPECT_GT(glm::dot(face_normal(c, t), centre - glm::dvec3(1, 2, centre.z)), 0);  // outward
  }
  EXPECT_NE(xml_error(mitsuba_scene(R"(<shape type="cylinder"><point name="p1" value="0"/>
      </shape>)"))
                .find("p0 and p1 must differ"),
            std::string::npos);
}

TEST(MitsubaShape, ShapeGroupsAndInstances) {
  Scene s = parse_xml(mitsuba_scene(R"(
    <shape type="shapegroup" id="tree"><shape type="cube"/><shape type="sphere"/></shape>
    <shape type="instance"><ref id="tree"/>
      <transform name="to_world"><translate x="5"/></transform></shape>
    <shape type="instance"><ref id="tree"/></shape>)"));
  ASSERT_EQ(s.groups.size(), 1u);
  EXPECT_EQ(s.groups[0].name, "tree");
  EXPECT_EQ(s.groups[0].shapes.size(), 2u);
  ASSERT_EQ(s.shapes.size(), 2u);
  EXPECT_EQ(s.shapes[0].kind, Shape::Kind::instance);
  EXPECT_EQ(s.shapes[0].group, 0u);
  EXPECT_EQ(s.shapes[0].to_world[3], glm::dvec4(5, 0, 0, 1));
  EXPECT_NE(xml_error(mitsuba_scene(R"(<shape type="shapegroup" id="g">
      <shape type="cube"><emitter type="area"/></shape></shape>)"))
                .find("a shapegroup's shapes cannot emit light"),
            std::string::npos);
  EXPECT_NE(xml_error(mitsuba_scene(R"(<shape type="cube" id="c"/>
      <shape type="instance"><ref id="c"/></shape>)"))
                .find("an instance places a shapegroup"),
            std::string::npos);
}

TEST(MitsubaEmitter, AreaEmittersOnShapes) {
  Shape s = shape_of(R"(<shape type="rectangle"><emitter type="area">
      <rgb name="radiance" value="17, 12, 4"/></emitter></shape>)");
  EXPECT_EQ(s.emission, glm::dvec3(17, 12, 4));
  EXPECT_FALSE(s.two_sided_emission);  // Mitsuba's area lights emit from the front only
  Shape sphere = shape_of(R"(<shape type="sphere"><emitter type="area">
      <float name="radiance" value="3"/><float name="sampling_weight" value="2"/></emitter></shape>)");
  EXPECT_EQ(sphere.emission, glm::dvec3(3));
  EXPECT_FALSE(shape_of(R"(<shape type="cube"/>)").is_emitter());
}

TEST(MitsubaShape, SerializedShapesAreReadWithTheirUvs) {
  // Two shapes with normals and uvs (the serialized reader's fuzzing seed).
  std::ifstream in(kSourceDir + "/fuzz/corpus/serialized_mesh/v4_normals_uvs.serialized",
                   std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_FALSE(bytes.empty());
  Scene s = parse_xml(mitsuba_scene(R"(<shape type="serialized">
      <string name="filename" value="meshes/m.serialized"/><integer name="shape_index" value="1"/>
      </shape>)"),
                      {{"meshes/m.serialized", bytes}});
  const Shape& shape = s.shapes.at(0);
  EXPECT_FALSE(shape.indices.empty());
  EXPECT_EQ(shape.uvs.size(), shape.positions.size());
  EXPECT_EQ(s.referenced_files, std::vector<std::string>{"meshes/m.serialized"});
  std::string xml = mitsuba_scene(R"(<shape type="serialized">
<string name="filename" value="m.serialized"/><integer name="shape_index" value="7"/></shape>)");
  EXPECT_NE(xml_error(xml, {{"m.serialized", bytes}})
                .find("test.xml: line " + std::to_string(line_of(xml, "<string")) +
                      ": <string name=\"filename\">: m.serialized"),
            std::string::npos);
}

TEST(MitsubaShape, UnsupportedShapesAndParametersNameTheirLine) {
  EXPECT_NE(xml_error(mitsuba_scene(R"(<shape type="cube"><medium type="homogeneous"
      name="inside"/></shape>)"))
                .find("<medium type=\"homogeneous\" name=\"inside\">: a shape's medium is named "
                      "\"interior\" or \"exterior\""),
            std::string::npos);
  EXPECT_NE(xml_error(mitsuba_scene(R"(<shape type="hair"/>)")).find("unsupported shape"),
            std::string::npos);
  EXPECT_NE(xml_error(mitsuba_scene(R"(<shape type="cube"><float name="radius" value="1"/>
      <float name="radius" value="2"/></shape>)"))
                .find("\"radius\" is given twice"),
            std::string::npos);
  EXPECT_NE(xml_error(mitsuba_scene(R"(<shape type="cube"><boolean name="flip_normals"
      value="yes"/></shape>)"))
                .find("\"yes\" must be true or false"),
            std::string::npos);
  EXPECT_NE(xml_error(mitsuba_scene(R"(<shape type="cube"><translate x="1"/></shape>)"))
                .find("a transform operation must be inside <transform name=\"to_world\">"),
            std::string::npos);
  EXPECT_NE(xml_error(mitsuba_scene(R"(<shape type="cube"><widget/></shape>)"))
                .find("<widget>: unknown element"),
            std::string::npos);
  EXPECT_NE(xml_error(mitsuba_scene(R"(<shape><float name="a" value="1"/></shape>)"))
                .find("<shape>: missing attribute \"type\""),
            std::string::npos);
}

// Curves: Mitsuba's file format, to_world moving the points but not the radii.
TEST(MitsubaShape, CurvesReadTheFileAndKeepTheirRadii) {
  const std::map<std::string, std::string> files = {
      {"c.txt", "-1 0 -1 0.1\n-0.5 0 1 0.1\n\n0 0 1 0.2\n0.5 0 -1 0.2\n1 0 1 0.3\n1 1 1 0.3\n"}};
  Shape linear = shape_of(R"(<shape type="linearcurve"><string name="filename" value="c.txt"/>
      <transform name="to_world"><scale x="2" y="1" z="0.5"/><translate z="3"/></transform>
      </shape>)", files);
  EXPECT_EQ(linear.kind, Shape::Kind::curves);
  EXPECT_EQ(linear.curve_basis, CurveBasis::linear);
  EXPECT_EQ(linear.curve_sizes, (std::vector<uint32_t>{2, 4}));
  EXPECT_EQ(linear.control_points[0], glm::dvec4(-2, 0, 2.5, double(0.1f)));
  EXPECT_EQ(linear.control_points[5], glm::dvec4(2, 1, 3.5, double(0.3f)));
  Shape bspline = shape_of(R"(<shape type="bsplinecurve"><string name="filename" value="c.txt"/>
      </shape>)", {{"c.txt", "0 0 0 1\n1 0 0 1\n2 0 0 1\n3 0 0 1\n4 0 0 1\n"}});
  EXPECT_EQ(bspline.curve_basis, CurveBasis::bspline);
  EXPECT_EQ(bspline.curve_sizes, (std::vector<uint32_t>{5}));
}

TEST(MitsubaShape, CurveErrorsNameTheElementFileAndLine) {
  const std::string bad = mitsuba_scene(R"(<shape type="bsplinecurve">
      <string name="filename" value="c.txt"/></shape>)");
  EXPECT_NE(xml_error(bad, {{"c.txt", "0 0 0 1\n1 0 0 1\n2 0 0 1\n3 0 0 1\n\n0 0 0 1\n"}})
                .find("c.txt: line 6: a B-spline curve needs at least 4 control points"),
            std::string::npos);
  EXPECT_NE(xml_error(bad, {{"c.txt", "0 0 0 1\n1 0 0 nan\n"}})
                .find("c.txt: line 2: the radius must be finite and >= 0 (got nan)"),
            std::string::npos);
  const std::string error = xml_error(bad, {});
  EXPECT_NE(error.find("line " + std::to_string(line_of(bad, "<string name=\"filename\"")) + ":"),
            std::string::npos)
      << error;
  EXPECT_NE(xml_error(mitsuba_scene(R"(<shape type="linearcurve">
      <string name="filename" value="c.txt"/><emitter type="area"/></shape>)"),
                      {{"c.txt", "0 0 0 1\n1 0 0 1\n"}})
                .find("curves cannot emit light"),
            std::string::npos);
}

}  // namespace
}  // namespace tessera
