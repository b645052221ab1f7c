// OBJ meshes with MTL materials: the McGuire Cornell boxes and small files written here.
#include <gtest/gtest.h>

#include "scene/native/native_test_support.h"

namespace tessera {
namespace {

using testing::error_of;
using testing::face_center;
using testing::face_normal;
using testing::parse;
using testing::scene_with_shapes;
using testing::shape_area;

Scene load_mcguire(const std::string& file) {
  return parse_scene(R"({"tessera": 1, "shapes": [{"type": "mesh", "file": ")" + file + R"("}]})",
                     folder_reader(TESSERA_SOURCE_DIR "/scenes/mcguire-cornell"));
}

const Shape& shape_of_group(const Scene& scene, const std::string& group) {
  for (const Shape& shape : scene.shapes) {
    if (shape.origin == "shapes[0] (" + group + ")") return shape;
  }
  throw std::runtime_error("no group " + group);
}

glm::dvec3 area_centroid(const Shape& shape) {
  glm::dvec3 sum(0);
  double area = 0;
  for (size_t t = 0; t < shape.indices.size(); ++t) {
    const glm::u32vec3& i = shape.indices[t];
    double a = 0.5 * glm::length(glm::cross(shape.positions[i.y] - shape.positions[i.x],
                                            shape.positions[i.z] - shape.positions[i.x]));
    sum += a * face_center(shape, t);
    area += a;
  }
  return sum / area;
}

/// Every triangle of `shape` faces along `direction` (within a few degrees).
void expect_all_face(const Shape& shape, const glm::dvec3& direction) {
  for (size_t t = 0; t < shape.indices.size(); ++t) {
    EXPECT_GT(glm::dot(face_normal(shape, t), direction), 0.99)
        << shape.origin << " triangle " << t;
  }
}

TEST(ObjLoader, McGuireSphereBoxMaterialsLightAndFacing) {
  Scene scene = load_mcguire("CornellBox-Sphere.obj");
  ASSERT_EQ(scene.shapes.size(), 8u);  // one per material
  size_t triangles = 0;
  for (const Shape& shape : scene.shapes) triangles += shape.indices.size();
  EXPECT_EQ(triangles, 2188u);
  EXPECT_EQ(scene.referenced_files,
            (std::vector<std::string>{"CornellBox-Sphere.obj", "CornellBox-Sphere.mtl"}));

  const Shape& left_sphere = shape_of_group(scene, "leftSphere");
  const Shape& right_sphere = shape_of_group(scene, "rightSphere");
  const Shape& light = shape_of_group(scene, "light");
  const Material& mirror = scene.materials[left_sphere.material];
  EXPECT_EQ(mirror.name, "CornellBox-Sphere.obj:leftSphere");
  EXPECT_EQ(mirror.type, MaterialType::mirror);  // illum 5
  const Material& glass = scene.materials[right_sphere.material];
  EXPECT_EQ(glass.type, MaterialType::glass);  // illum 7
  EXPECT_EQ(glass.ior, 2.5);                   // Ni
  const Material& red = scene.materials[shape_of_group(scene, "leftWall").material];
  EXPECT_EQ(red.type, MaterialType::diffuse);
  testing::expect_near(red.reflectance.value, {0.63, 0.065, 0.05}, 1e-12);  // Kd
  EXPECT_EQ(light.emission, glm::dvec3(10, 10, 10));                  // Ke
  EXPECT_FALSE(light.two_sided_emission);
  int emitters = 0;
  for (const Shape& shape : scene.shapes) emitters += shape.is_emitter();
  EXPECT_EQ(emitters, 1);

  // Facing, from the winding: the walls face into the box, the light faces down, the spheres
  // face outward (their smooth normals agree).
  expect_all_face(shape_of_group(scene, "floor"), {0, 1, 0});
  expect_all_face(shape_of_group(scene, "ceiling"), {0, -1, 0});
  expect_all_face(shape_of_group(scene, "backWall"), {0, 0, 1});
  expect_all_face(shape_of_group(scene, "leftWall"), {1, 0, 0});
  expect_all_face(shape_of_group(scene, "rightWall"), {-1, 0, 0});
  expect_all_face(light, {0, -1, 0});
  for (const Shape* sphere : {&left_sphere, &right_sphere}) {
    glm::dvec3 center = area_centroid(*sphere);
    ASSERT_FALSE(sphere->normals.empty());
    for (size_t t = 0; t < sphere->indices.size(); ++t) {
      glm::dvec3 n = face_normal(*sphere, t);
      EXPECT_GT(glm::dot(n, face_center(*sphere, t) - center), 0) << sphere->origin << " " << t;
      const glm::u32vec3& i = sphere->indices[t];
      glm::dvec3 smooth = sphere->normals[i.x] + sphere->normals[i.y] + sphere->normals[i.z];
      EXPECT_GT(glm::dot(n, smooth), 0) << sphere->origin << " " << t;
    }
  }
}

TEST(ObjLoader, McGuireOriginalBox) {
  Scene scene = load_mcguire("CornellBox-Original.obj");
  size_t triangles = 0;
  for (const Shape& shape : scene.shapes) triangles += shape.indices.size();
  EXPECT_EQ(triangles, 36u);  // 18 quads
  const Shape& light = shape_of_group(scene, "light");
  EXPECT_EQ(light.emission, glm::dvec3(17, 12, 4));
  expect_all_face(light, {0, -1, 0});
  EXPECT_TRUE(light.normals.empty());  // the file has no vn
}

const char* kTwoMaterialObj = R"(mtllib m.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
usemtl red
f 1 2 3 4
usemtl lamp
f 1 5 6 2
)";
const char* kTwoMaterialMtl = R"(newmtl red
Kd 0.9 0.1 0.1
Ka 1 1 1
Ks 0.5 0.5 0.5
map_Kd red.png
newmtl lamp
Kd 0 0 0
Ke 5 5 5
)";

TEST(ObjLoader, MaterialsComeFromTheMtlUnlessTheShapeNamesOne) {
  std::map<std::string, std::string> files = {{"meshes/m.obj", kTwoMaterialObj},
                                              {"meshes/m.mtl", kTwoMaterialMtl}};
  Scene scene = parse(scene_with_shapes(R"({"type": "mesh", "file": "meshes/m.obj"})"), files);
  ASSERT_EQ(scene.shapes.size(), 2u);
  EXPECT_EQ(scene.materials[scene.shapes[0].material].name, "meshes/m.obj:red");
  EXPECT_EQ(scene.materials[scene.shapes[0].material].reflectance.value, glm::dvec3(0.9, 0.1, 0.1));
  EXPECT_FALSE(scene.shapes[0].is_emitter());
  EXPECT_EQ(scene.shapes[1].emission, glm::dvec3(5));
  EXPECT_EQ(scene.shapes[1].origin, "shapes[0] (lamp)");
  EXPECT_EQ(scene.referenced_files, (std::vector<std::string>{"meshes/m.obj", "meshes/m.mtl"}));

  // With "material", the MTL is not read at all (here it is missing) and there is one shape.
  Scene overridden =
      parse(scene_with_shapes(R"({"type": "mesh", "file": "meshes/m.obj", "material": "white"})"),
            {{"meshes/m.obj", kTwoMaterialObj}});
  ASSERT_EQ(overridden.shapes.size(), 1u);
  EXPECT_EQ(overridden.shapes[0].indices.size(), 4u);
  EXPECT_EQ(overridden.materials[overridden.shapes[0].material].name, "white");
  EXPECT_FALSE(overridden.shapes[0].is_emitter());
  EXPECT_EQ(overridden.referenced_files, (std::vector<std::string>{"meshes/m.obj"}));
}

TEST(ObjLoader, TwoSidedAndPowerApplyToEveryGroup) {
  std::map<std::string, std::string> files = {{"m.obj", kTwoMaterialObj},
                                              {"m.mtl", kTwoMaterialMtl}};
  Scene scene = parse(
      scene_with_shapes(
          R"({"type": "mesh", "file": "m.obj", "two_sided": true, "power": 6.283185307179586})"),
      files);
  ASSERT_EQ(scene.shapes.size(), 2u);
  EXPECT_EQ(scene.materials[scene.shapes[0].material].name, "m.obj:red (two-sided)");
  EXPECT_TRUE(scene.materials[scene.shapes[0].material].two_sided);
  // Total area 2, two-sided: radiance = 2 pi / (2 pi * 2) = 0.5 on both groups (Ke ignored).
  for (const Shape& shape : scene.shapes) {
    EXPECT_NEAR(shape.emission.x, 0.5, 1e-12);
    EXPECT_TRUE(shape.two_sided_emission);
  }
}

TEST(ObjLoader, PolygonsAreTriangulatedKeepingTheirWinding) {
  const char* obj = R"(v 0 0 0
v 2 0 0
v 3 1 0
v 1 2 0
v -1 1 0
f 1 2 3 4 5
f 1 2 3 4
)";
  Scene scene =
      parse(scene_with_shapes(R"({"type": "mesh", "file": "p.obj", "material": "white"})"),
            {{"p.obj", obj}});
  const Shape& shape = scene.shapes[0];
  ASSERT_EQ(shape.indices.size(), 5u);  // 3 from the pentagon, 2 from the quad
  for (size_t t = 0; t < shape.indices.size(); ++t) {
    EXPECT_NEAR(face_normal(shape, t).z, 1.0, 1e-12) << t;
  }
  EXPECT_NEAR(shape_area(shape), 5 + 3.5, 1e-12);  // shoelace areas of the two polygons
}

TEST(ObjLoader, NormalsAreKeptUnlessFaceNormals) {
  const char* obj = R"(v 0 0 0
v 1 0 0
v 0 1 0
vn 0 0 2
f 1//1 2//1 3//1
)";
  std::map<std::string, std::string> files = {{"n.obj", obj}};
  Scene smooth =
      parse(scene_with_shapes(R"({"type": "mesh", "file": "n.obj", "material": "white"})"), files);
  ASSERT_EQ(smooth.shapes[0].normals.size(), 3u);
  EXPECT_EQ(smooth.shapes[0].normals[0], glm::dvec3(0, 0, 1));
  Scene flat =
      parse(scene_with_shapes(
                R"({"type": "mesh", "file": "n.obj", "material": "white", "face_normals": true})"),
            files);
  EXPECT_TRUE(flat.shapes[0].normals.empty());
}

TEST(ObjLoader, TextureCoordinatesFlipVAsMitsubaDoes) {
  // Vertex 1 is used with two different vt: it becomes two vertices. Mitsuba 3 reads vt (u, v)
  // as (u, 1 - v) (checked with its Python build: vt 0.1 0.2 gives uv (0.1, 0.8)).
  const char* obj = R"(v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
vt 0.1 0.2
vt 0.3 0.4
vt 0.5 0.6
vt 0.7 0.75
f 1/1 2/2 3/3
f 1/4 3/3 4/1
)";
  std::map<std::string, std::string> files = {{"t.obj", obj}};
  Scene scene =
      parse(scene_with_shapes(R"({"type": "mesh", "file": "t.obj", "material": "white"})"), files);
  const Shape& shape = scene.shapes[0];
  ASSERT_EQ(shape.positions.size(), 5u);
  ASSERT_EQ(shape.uvs.size(), 5u);
  auto expect_uv = [](const glm::dvec2& uv, double u, double v) {
    EXPECT_NEAR(uv.x, u, 1e-15);  // tinyobjloader's number parser is not always exact
    EXPECT_NEAR(uv.y, v, 1e-15);
  };
  expect_uv(shape.uvs[shape.indices[0].x], 0.1, 0.8);
  expect_uv(shape.uvs[shape.indices[0].z], 0.5, 0.4);
  expect_uv(shape.uvs[shape.indices[1].x], 0.7, 0.25);
  EXPECT_EQ(shape.positions[shape.indices[1].x], glm::dvec3(0, 0, 0));
  EXPECT_NE(shape.indices[0].x, shape.indices[1].x);

  // A group with a corner without vt has no uvs.
  files["t.obj"] = std::string(obj) + "f 2 3 4\n";
  scene = parse(scene_with_shapes(R"({"type": "mesh", "file": "t.obj", "material": "white"})"),
                files);
  EXPECT_TRUE(scene.shapes[0].uvs.empty());
  files["t.obj"] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/2\n";
  EXPECT_EQ(error_of(scene_with_shapes(R"({"type": "mesh", "file": "t.obj", "material": "white"})"),
                     files),
            "shapes[0].file: t.obj: line 5: a face refers to texture coordinate 2 but the file has 1");
}

TEST(ObjLoader, DegenerateFacesAreDroppedAndCounted) {
  const char* obj = R"(v 0 0 0
v 1 0 0
v 0 1 0
v 2 0 0
f 1 2 3
f 1 2 4
f 1 1 3
)";
  Scene scene =
      parse(scene_with_shapes(R"({"type": "mesh", "file": "d.obj", "material": "white"})"),
            {{"d.obj", obj}});
  EXPECT_EQ(scene.shapes[0].indices.size(), 1u);
  EXPECT_EQ(scene.shapes[0].dropped_triangles, 2u);
  const char* flat = "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n";
  EXPECT_EQ(error_of(scene_with_shapes(R"({"type": "mesh", "file": "f.obj", "material": "white"})"),
                     {{"f.obj", flat}}),
            "shapes[0].file: f.obj: no triangles (1 degenerate faces dropped)");
}

TEST(ObjLoader, BadFilesNameTheFileAndWhatIsWrong) {
  auto error = [](const std::string& obj, std::map<std::string, std::string> more = {},
                  const std::string& extra = "") {
    more["meshes/m.obj"] = obj;
    return error_of(scene_with_shapes(R"({"type": "mesh", "file": "meshes/m.obj")" + extra + "}"),
                    more);
  };
  EXPECT_EQ(
      error("mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n"),
      "shapes[0].file: meshes/m.obj: mtllib: meshes/m.mtl: no such file in the scene's folder");
  EXPECT_EQ(error("mtllib ../m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
            "shapes[0].file: meshes/m.obj: mtllib: path must stay inside the scene's folder "
            "(\"../m.mtl\")");
  EXPECT_EQ(
      error("mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl hot\nf 1 2 3\n",
            {{"meshes/m.mtl", "newmtl hot\nKd 1.5 0 0\n"}}),
      "shapes[0].file: meshes/m.obj: MTL material \"hot\": Kd[0] must be in [0, 1] (got 1.5)");
  EXPECT_EQ(error("mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl g\nf 1 2 3\n",
                  {{"meshes/m.mtl", "newmtl g\nillum 7\nNi 0\n"}}),
            "shapes[0].file: meshes/m.obj: MTL material \"g\": Ni must be > 0 for glass (illum 7) "
            "(got 0)");
  EXPECT_EQ(error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"),
            "shapes[0].file: meshes/m.obj: line 4: a face refers to vertex 9 but the file has 3");
  // As written, never wrapped into an int or resolved from the end.
  EXPECT_EQ(error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999\n"),
            "shapes[0].file: meshes/m.obj: line 4: a face refers to vertex 99999999999 but the file "
            "has 3");
  EXPECT_EQ(error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999\n"),
            "shapes[0].file: meshes/m.obj: line 4: a face refers to vertex 99999999999999999999 "
            "but the file has 3");
  EXPECT_EQ(error("v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 0 1 0\n"),
            "shapes[0].file: meshes/m.obj: line 3: a face refers to vertex -3, 3 back, but only 2 "
            "come before it");
  EXPECT_EQ(error("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n"),
            "shapes[0].file: meshes/m.obj: line 5: a face refers to texture coordinate 2 but the "
            "file has 1");
  EXPECT_EQ(error("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//-4\n"),
            "shapes[0].file: meshes/m.obj: line 5: a face refers to normal -4, 4 back, but only 1 "
            "come before it");
  EXPECT_EQ(error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
            "shapes[0].material: required (the mesh file gives no material to some of its faces)");
  EXPECT_EQ(error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n", {}, R"(, "material": "white")"),
            "shapes[0].file: meshes/m.obj: line 4: a face refers to vertex 0 (OBJ counts from 1)");
  std::string big = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf";
  for (int k = 0; k < 300; ++k) big += " " + std::to_string(1 + k % 3);
  EXPECT_EQ(error(big + "\n", {}, R"(, "material": "white")"),
            "shapes[0].file: meshes/m.obj: a face has more than 255 vertices");
  EXPECT_EQ(error("v 0 0 0\n", {}, R"(, "material": "white")"),
            "shapes[0].file: meshes/m.obj: no triangles (0 degenerate faces dropped)");
}

}  // namespace
}  // namespace tessera
