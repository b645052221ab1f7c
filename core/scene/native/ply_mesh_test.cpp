// PLY meshes: the three encodings written here, the Stanford bunny, and broken files.
#include "scene/mesh/ply_loader.h"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

#include "scene/native/native_test_support.h"

namespace tessera {
namespace {

using testing::error_of;
using testing::face_normal;
using testing::parse;
using testing::scene_with_shapes;
using testing::shape_area;

/// Writes PLY files value by value in any of the three encodings.
class PlyBuilder {
 public:
  explicit PlyBuilder(std::string format) : format_(std::move(format)) {}

  PlyBuilder& header(const std::string& line) {
    header_ += line + "\n";
    return *this;
  }

  template <typename T>
  PlyBuilder& value(T v) {
    if (format_ == "ascii") {
      std::ostringstream text;
      text.precision(17);
      if constexpr (std::is_integral_v<T>)
        text << int64_t(v);
      else
        text << v;
      body_ += text.str() + " ";
      return *this;
    }
    char raw[sizeof(T)];
    std::memcpy(raw, &v, sizeof(T));
    bool big = format_ == "binary_big_endian";
    if (big != (std::endian::native == std::endian::big)) std::reverse(raw, raw + sizeof(T));
    body_.append(raw, sizeof(T));
    return *this;
  }

  PlyBuilder& body_text(const std::string& text) {
    body_ += text;
    return *this;
  }

  PlyBuilder& end_row() {
    if (format_ == "ascii") body_ += "\n";
    return *this;
  }

  std::string bytes() const {
    return "ply\nformat " + format_ + " 1.0\ncomment written by ply_loader_test\n" + header_ +
           "end_header\n" + body_;
  }

 private:
  std::string format_;
  std::string header_;
  std::string body_;
};

/// A unit square (one quad face) and a triangle, with properties in an unusual order, types
/// mixed, and things to skip: a colour per vertex, flags per face, an "edge" element.
std::string square_and_triangle(const std::string& format) {
  PlyBuilder ply(format);
  ply.header("element vertex 5")
      .header("property float y")
      .header("property double x")
      .header("property uchar red")
      .header("property float z")
      .header("element edge 2")
      .header("property int vertex1")
      .header("property int vertex2")
      .header("element face 2")
      .header("property uchar flags")
      .header("property list uchar int vertex_indices");
  const double xyz[5][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}};
  for (const auto& p : xyz)
    ply.value(float(p[1])).value(double(p[0])).value(uint8_t(200)).value(float(p[2])).end_row();
  ply.value(int32_t(0)).value(int32_t(1)).end_row().value(int32_t(1)).value(int32_t(2)).end_row();
  ply.value(uint8_t(7))
      .value(uint8_t(4))
      .value(int32_t(0))
      .value(int32_t(1))
      .value(int32_t(2))
      .value(int32_t(3))
      .end_row();
  ply.value(uint8_t(7))
      .value(uint8_t(3))
      .value(int32_t(0))
      .value(int32_t(4))
      .value(int32_t(1))
      .end_row();
  return ply.bytes();
}

Shape load_ply_shape(const std::string& bytes, const std::string& extra = "") {
  Scene scene = parse(
      scene_with_shapes(R"({"type": "mesh", "file": "m.ply", "material": "white")" + extra + "}"),
      {{"m.ply", bytes}});
  EXPECT_EQ(scene.shapes.size(), 1u);
  return scene.shapes.at(0);
}

std::string ply_error(const std::string& bytes) {
  return error_of(scene_with_shapes(R"({"type": "mesh", "file": "m.ply", "material": "white"})"),
                  {{"m.ply", bytes}});
}

TEST(PlyLoader, TextureCoordinatesUnderEachOfMitsubasNames) {
  // Mitsuba 3 keeps PLY uvs as stored (checked with its Python build for u/v, s/t and
  // texture_u/texture_v).
  for (const char* format : {"ascii", "binary_little_endian"}) {
    for (auto [u, v] : {std::pair{"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"}}) {
      SCOPED_TRACE(std::string(format) + " " + u);
      PlyBuilder ply(format);
      ply.header("element vertex 3")
          .header("property float x")
          .header(std::string("property double ") + v)
          .header("property float y")
          .header("property float z")
          .header(std::string("property float ") + u)
          .header("element face 1")
          .header("property list uchar int vertex_indices");
      const double rows[3][5] = {{0, 0.2, 0, 0, 0.1}, {1, 0.4, 0, 0, 0.3}, {1, 0.75, 1, 0, 0.5}};
      for (const auto& r : rows) {
        ply.value(float(r[0])).value(double(r[1])).value(float(r[2])).value(float(r[3]));
        ply.value(float(r[4])).end_row();
      }
      ply.value(uint8_t(3)).value(int32_t(0)).value(int32_t(1)).value(int32_t(2)).end_row();
      Shape shape = load_ply_shape(ply.bytes());
      ASSERT_EQ(shape.uvs.size(), 3u);
      EXPECT_EQ(shape.uvs[0], glm::dvec2(double(0.1f), 0.2));
      EXPECT_EQ(shape.uvs[2], glm::dvec2(0.5, 0.75));
    }
  }
  EXPECT_TRUE(load_ply_shape(square_and_triangle("ascii")).uvs.empty());
  PlyBuilder bad("ascii");
  bad.header("element vertex 3")
      .header("property float x")
      .header("property float y")
      .header("property float z")
      .header("property float u")
      .header("property float v")
      .header("element face 1")
      .header("property list uchar int vertex_indices");
  bad.value(0).value(0).value(0).value(0).value(0).end_row();
  bad.value(1).value(0).value(0).value(0).end_row();
  bad.body_text("inf 0\n1 1 0 0 0\n3 0 1 2\n");
  EXPECT_EQ(ply_error(bad.bytes()),
            "shapes[0].file: m.ply: line 15 (element vertex, row 1): texture coordinate is not a "
            "finite number");
}

TEST(PlyLoader, AllThreeEncodingsGiveTheSameMesh) {
  for (const char* format : {"ascii", "binary_little_endian", "binary_big_endian"}) {
    SCOPED_TRACE(format);
    Shape shape = load_ply_shape(square_and_triangle(format));
    ASSERT_EQ(shape.positions.size(), 5u);
    EXPECT_EQ(shape.positions[2], glm::dvec3(1, 1, 0));
    EXPECT_EQ(shape.positions[4], glm::dvec3(0, 0, 1));
    ASSERT_EQ(shape.indices.size(), 3u);  // the quad is fan-triangulated
    EXPECT_EQ(shape.indices[0], glm::u32vec3(0, 1, 2));
    EXPECT_EQ(shape.indices[1], glm::u32vec3(0, 2, 3));
    EXPECT_EQ(shape.indices[2], glm::u32vec3(0, 4, 1));
    EXPECT_DOUBLE_EQ(shape_area(shape), 1.5);
    EXPECT_EQ(face_normal(shape, 0), glm::dvec3(0, 0, 1));
    EXPECT_EQ(face_normal(shape, 2), glm::dvec3(0, 1, 0));
    EXPECT_TRUE(shape.normals.empty());
    EXPECT_EQ(shape.dropped_triangles, 0u);
  }
}

TEST(PlyLoader, VertexIndexListWithUintCountsAndNormals) {
  for (const char* format : {"ascii", "binary_big_endian"}) {
    SCOPED_TRACE(format);
    PlyBuilder ply(format);
    ply.header("element vertex 3")
        .header("property float x")
        .header("property float y")
        .header("property float z")
        .header("property float nx")
        .header("property float ny")
        .header("property float nz")
        .header("element face 2")
        .header("property list uint uint vertex_index");
    const float rows[3][6] = {{0, 0, 0, 0, 0, 3}, {1, 0, 0, 0, 0, 1}, {0, 1, 0, 0, 0, 1}};
    for (const auto& r : rows) {
      for (float v : r) ply.value(v);
      ply.end_row();
    }
    ply.value(uint32_t(3)).value(uint32_t(0)).value(uint32_t(1)).value(uint32_t(2)).end_row();
    ply.value(uint32_t(2)).value(uint32_t(0)).value(uint32_t(1)).end_row();  // a 2-gon: dropped
    Shape shape = load_ply_shape(ply.bytes());
    ASSERT_EQ(shape.indices.size(), 1u);
    EXPECT_EQ(shape.dropped_triangles, 1u);
    ASSERT_EQ(shape.normals.size(), 3u);
    EXPECT_EQ(shape.normals[0], glm::dvec3(0, 0, 1));  // unit length
    EXPECT_TRUE(load_ply_shape(ply.bytes(), R"(, "face_normals": true)").normals.empty());
  }
}

TEST(PlyLoader, StanfordBunny) {
  Scene scene = parse_scene(
      R"({"tessera": 1, "materials": {"white": {}}, "shapes": [
          {"type": "mesh", "file": "meshes/bunny.ply", "material": "white"},
          {"type": "mesh", "file": "meshes/bunny_lowres.ply", "material": "white"}]})",
      folder_reader(TESSERA_SOURCE_DIR "/scenes"));
  const Shape& bunny = scene.shapes[0];
  EXPECT_EQ(bunny.positions.size(), 35947u);
  EXPECT_EQ(bunny.indices.size() + bunny.dropped_triangles, 69451u);
  EXPECT_EQ(bunny.indices.size(), 69451u);  // no degenerate triangle in this scan
  EXPECT_GT(shape_area(bunny), 0.0);
  EXPECT_EQ(scene.shapes[1].indices.size() + scene.shapes[1].dropped_triangles, 948u);
  EXPECT_EQ(scene.referenced_files,
            (std::vector<std::string>{"meshes/bunny.ply", "meshes/bunny_lowres.ply"}));
}

TEST(PlyLoader, TruncatedFiles) {
  std::string binary = square_and_triangle("binary_little_endian");
  EXPECT_EQ(ply_error(binary.substr(0, binary.size() - 3)),
            "shapes[0].file: m.ply: element face, row 1: unexpected end of file");
  std::string ascii = square_and_triangle("ascii");
  EXPECT_EQ(ply_error(ascii.substr(0, ascii.size() - 4)),
            "shapes[0].file: m.ply: line 24 (element face, row 1): unexpected end of file");
  // A count that cannot fit in what is left of the file is refused before reading anything.
  std::string absurd = binary;
  absurd.replace(absurd.find("element face 2"), 14, "element face 4000000000");
  EXPECT_EQ(ply_error(absurd),
            "shapes[0].file: m.ply: element \"face\" declares 4000000000 rows, which cannot fit "
            "in the file (133 bytes of data)");
}

TEST(PlyLoader, IndicesOutOfRange) {
  for (const char* format : {"ascii", "binary_little_endian"}) {
    PlyBuilder ply(format);
    ply.header("element vertex 3")
        .header("property float x")
        .header("property float y")
        .header("property float z")
        .header("element face 1")
        .header("property list uchar int vertex_indices");
    for (int i = 0; i < 3; ++i) ply.value(float(i == 1)).value(float(i == 2)).value(0.0f).end_row();
    ply.value(uint8_t(3)).value(int32_t(0)).value(int32_t(1)).value(int32_t(3)).end_row();
    std::string where =
        std::string(format) == "ascii" ? "line 14 (element face, row 0)" : "element face, row 0";
    EXPECT_EQ(ply_error(ply.bytes()),
              "shapes[0].file: m.ply: " + where + ": vertex index 3 out of range (3 vertices)");
  }
}

TEST(PlyLoader, BadHeadersAndValues) {
  EXPECT_EQ(ply_error("solid cube\n"),
            "shapes[0].file: m.ply: not a PLY file (it does not start with \"ply\")");
  EXPECT_EQ(ply_error("ply\nformat binary_middle_endian 1.0\nend_header\n"),
            "shapes[0].file: m.ply: line 2: unknown format \"binary_middle_endian\"");
  EXPECT_EQ(ply_error("ply\nformat ascii 1.0\nproperty float x\nend_header\n"),
            "shapes[0].file: m.ply: line 3: property before any element");
  EXPECT_EQ(ply_error("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"),
            "shapes[0].file: m.ply: the header has no end_header line");
  EXPECT_EQ(
      ply_error("ply\nformat ascii 1.0\nelement vertex 1\nproperty quaternion x\nend_header\n"),
      "shapes[0].file: m.ply: line 4: unknown property type \"quaternion\"");
  EXPECT_EQ(ply_error("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nelement face 0\n"
                      "property list uchar int vertex_indices\nend_header\n1\n"),
            "shapes[0].file: m.ply: element vertex has no property y");
  EXPECT_EQ(
      ply_error("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
                "property float z\nend_header\n"),
      "shapes[0].file: m.ply: no face element (only triangle meshes are supported)");
  EXPECT_EQ(
      ply_error("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                "property float z\nelement face 0\nproperty list uchar int vertex_indices\n"
                "end_header\n0 zero 0\n"),
      "shapes[0].file: m.ply: line 10 (element vertex, row 0): expected a number (got \"zero\")");
  EXPECT_EQ(
      ply_error("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                "property float z\nelement face 0\nproperty list uchar int vertex_indices\n"
                "end_header\n0 inf 0\n"),
      "shapes[0].file: m.ply: line 10 (element vertex, row 0): vertex coordinate is not a "
      "finite number");
  EXPECT_EQ(
      ply_error("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                "end_header\n0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n"),
      "shapes[0].file: m.ply: no triangles (1 degenerate faces dropped)");
}

TEST(PlyLoader, RefusesHugeMeshesBeforeAllocating) {
  // Rows of zero size fit in any file, so only the limit stops this one.
  std::string ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 100000001\n"
      "element face 0\nproperty list uchar int vertex_indices\nend_header\n";
  EXPECT_THROW(load_ply(ply, "huge.ply", true), SceneError);
  try {
    load_ply(ply, "huge.ply", true);
  } catch (const SceneError& e) {
    EXPECT_STREQ(e.what(), "huge.ply: 100000001 vertices (at most 100000000)");
  }
}

}  // namespace
}  // namespace tessera
