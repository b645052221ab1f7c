// Mitsuba serialized meshes: files written here field by field (versions 3 and 4, float and
// double, several shapes) and broken ones.
#include "scene/mesh/serialized_loader.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "scene/mesh/mesh_file.h"
#include "scene/scene_error.h"
#include "scene/mesh/serialized_test_files.h"
#include "scene/scene_test_support.h"

namespace tessera {
namespace {

using testing::Bytes;
using testing::compress;
using testing::file_bytes;
using testing::quad;
using testing::shape_bytes;
using testing::ShapeSpec;

std::string serialized_error(const std::string& bytes, int shape_index = 0) {
  try {
    load_serialized_mesh(bytes, "m.serialized", shape_index, true);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(SerializedLoader, ReadsPositionsNormalsUvsAndSkipsColours) {
  ShapeSpec s = quad(0.25);
  s.flags = 0x1000 | 0x1 | 0x2 | 0x8;
  s.name = "Plane.001";
  s.normals = {0, 0, 1, 0, 0, 1, 0, 0, 2, 0, 0, 1};
  s.uvs = {0, 0, 1, 0, 1, 1, 0, 0.75};
  s.colors = {1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1};
  SerializedMesh m = load_serialized_mesh(file_bytes({s}), "m.serialized", 0, true);
  EXPECT_EQ(m.shape_name, "Plane.001");
  ASSERT_EQ(m.mesh.positions.size(), 4u);
  EXPECT_EQ(m.mesh.positions[2], glm::dvec3(1, 1, 0.25));
  ASSERT_EQ(m.mesh.normals.size(), 4u);
  EXPECT_EQ(m.mesh.normals[2], glm::dvec3(0, 0, 2));  // as stored; callers normalise
  ASSERT_EQ(m.mesh.uvs.size(), 4u);
  EXPECT_EQ(m.mesh.uvs[3], glm::dvec2(0, 0.75));
  ASSERT_EQ(m.mesh.indices.size(), 2u);
  EXPECT_EQ(m.mesh.indices[1], glm::u32vec3(0, 2, 3));

  SerializedMesh faceted = load_serialized_mesh(file_bytes({s}), "m.serialized", 0, false);
  EXPECT_TRUE(faceted.mesh.normals.empty());
  EXPECT_EQ(faceted.mesh.uvs.size(), 4u);
}

TEST(SerializedLoader, DoublePrecisionKeepsEveryBit) {
  ShapeSpec s = quad(0.1);
  s.flags = 0x2000 | 0x2;
  s.positions[0] = 1.0 / 3.0;
  s.uvs = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8};
  SerializedMesh m = load_serialized_mesh(file_bytes({s}), "m.serialized", 0, true);
  EXPECT_EQ(m.mesh.positions[0].x, 1.0 / 3.0);
  EXPECT_EQ(m.mesh.positions[0].z, 0.1);
  EXPECT_EQ(m.mesh.uvs[2], glm::dvec2(0.5, 0.6));
  // Single precision rounds to float, as the file stores it.
  s.flags = 0x1000 | 0x2;
  m = load_serialized_mesh(file_bytes({s}), "m.serialized", 0, true);
  EXPECT_EQ(m.mesh.positions[0].x, double(float(1.0 / 3.0)));
}

TEST(SerializedLoader, ShapeIndexFindsEachShapeInVersions3And4) {
  std::vector<ShapeSpec> shapes = {quad(0), quad(1), quad(2)};
  shapes[1].name = "second";
  for (uint16_t version : {3, 4}) {
    std::string file = file_bytes(shapes, version);
    for (int index = 0; index < 3; ++index) {
      SerializedMesh m = load_serialized_mesh(file, "m.serialized", index, true);
      EXPECT_EQ(m.mesh.positions[0].z, index) << "version " << version;
      EXPECT_EQ(m.shape_name, version == 4 ? shapes[index].name : "");
    }
    EXPECT_EQ(serialized_error(file, 3),
              "m.serialized: shape_index 3 out of range (the file holds 3 shapes)");
  }
}

TEST(SerializedLoader, FaceNormalsFlagIsIgnoredAsMitsuba3Does) {
  ShapeSpec s = quad(0);
  s.flags = 0x1000 | 0x1 | 0x10;
  s.normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  EXPECT_EQ(load_serialized_mesh(file_bytes({s}), "m", 0, true).mesh.normals.size(), 4u);
}

TEST(SerializedLoader, UnusableNormalsAreDropped) {
  ShapeSpec s = quad(0);
  s.flags = 0x1000 | 0x1;
  s.normals = {0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 1};
  EXPECT_TRUE(load_serialized_mesh(file_bytes({s}), "m", 0, true).mesh.normals.empty());
}

TEST(SerializedLoader, RefusesBrokenFilesNamingThem) {
  std::string good = file_bytes({quad(0)});
  EXPECT_EQ(serialized_error("\x1c"), "m.serialized: truncated: no serialized file header");
  EXPECT_EQ(serialized_error("PK\x03\x04" + good.substr(4)),
            "m.serialized: not a Mitsuba serialized mesh (bad magic number)");
  std::string v5 = good;
  v5[2] = 5;
  EXPECT_EQ(serialized_error(v5),
            "m.serialized: unsupported serialized format version 5 (expected 3 or 4)");
  EXPECT_EQ(serialized_error(good, -1), "m.serialized: shape_index must be >= 0 (got -1)");

  // The compressed stream cut short: the triangle indices are missing.
  std::string raw_shape = shape_bytes(quad(0), 4);
  std::string body;
  {
    Bytes b;
    b.put<uint32_t>(0x1000).text("q").put<uint64_t>(4).put<uint64_t>(2);
    for (int i = 0; i < 12; ++i) b.put<float>(0.5f * i);
    body = b.data;  // no indices at all
  }
  std::string cut = raw_shape.substr(0, 4) + compress(body);
  EXPECT_EQ(serialized_error(cut),
            "m.serialized: truncated: the compressed data ends in the triangle indices");
  std::string short_file = serialized_error(good.substr(0, 20));
  EXPECT_EQ(short_file.rfind("m.serialized: truncated", 0), 0u) << short_file;
  std::string corrupt = good;
  for (size_t i = 8; i < 20; ++i) corrupt[i] = char(0xff);
  EXPECT_NE(serialized_error(corrupt).find("m.serialized: "), std::string::npos);
  EXPECT_NE(serialized_error(corrupt), "(no error)");
}

TEST(SerializedLoader, RefusesBadValues) {
  ShapeSpec s = quad(0);
  s.indices[4] = 4;
  EXPECT_EQ(serialized_error(file_bytes({s})),
            "m.serialized: triangle 1: vertex index 4 out of range (4 vertices)");
  s = quad(0);
  s.positions[7] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(serialized_error(file_bytes({s})), "m.serialized: vertex 2: position is not finite");
  s = quad(0);
  s.flags |= 0x2;
  s.uvs = {0, 0, 1, 0, 1, std::numeric_limits<double>::infinity(), 0, 1};
  EXPECT_EQ(serialized_error(file_bytes({s})), "m.serialized: vertex 2: texture coordinate is not finite");
}

TEST(SerializedLoader, RefusesCountsBeforeAllocating) {
  Bytes b;
  b.put<uint32_t>(0x1000).text("").put<uint64_t>(uint64_t(1) << 40).put<uint64_t>(1);
  std::string huge = std::string("\x1c\x04\x04\x00", 4) + compress(b.data);
  EXPECT_EQ(serialized_error(huge), "m.serialized: 1099511627776 vertices (at most 100000000)");
  Bytes c;
  c.put<uint32_t>(0x2000).text("").put<uint64_t>(50'000'000).put<uint64_t>(50'000'000);
  std::string big = std::string("\x1c\x04\x04\x00", 4) + compress(c.data);
  EXPECT_NE(serialized_error(big).find("more than 64 times as many"), std::string::npos)
      << serialized_error(big);
  EXPECT_EQ(serialized_load_bytes(big, "m.serialized"), 0u);
}

// 20M zero vertices and triangles deflate to under half a megabyte (about 1029:1): refused from
// the header, before the 0.5 GB of arrays it declares are allocated.
TEST(SerializedLoader, RefusesADecompressionBombFromItsHeader) {
  const uint64_t count = 20'000'000;
  Bytes head;
  head.put<uint32_t>(0x1000).text("bomb").put<uint64_t>(count).put<uint64_t>(count);
  z_stream z{};
  // Z_RLE: the same stream as level 9 gives for zeros (466,792 bytes), in a fifth of the time.
  ASSERT_EQ(deflateInit2(&z, 9, Z_DEFLATED, 15, 8, Z_RLE), Z_OK);
  std::string out(1 << 20, '\0');
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = uInt(out.size());
  z.next_in = reinterpret_cast<Bytef*>(head.data.data());
  z.avail_in = uInt(head.data.size());
  ASSERT_EQ(deflate(&z, Z_NO_FLUSH), Z_OK);
  const std::string zeros(1 << 20, '\0');
  for (uint64_t left = count * 24; left > 0;) {  // 12 bytes per vertex and per triangle
    const uInt n = uInt(std::min<uint64_t>(left, zeros.size()));
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(zeros.data()));
    z.avail_in = n;
    ASSERT_EQ(deflate(&z, Z_NO_FLUSH), Z_OK);
    left -= n;
  }
  ASSERT_EQ(deflate(&z, Z_FINISH), Z_STREAM_END);
  out.resize(z.total_out);
  deflateEnd(&z);
  const std::string bomb = std::string("\x1c\x04\x04\x00", 4) + out;
  EXPECT_LT(bomb.size(), 500'000u);
  const std::string error = serialized_error(bomb);
  EXPECT_EQ(error.rfind("m.serialized: 20000000 vertices and 20000000 triangles (480000000 bytes)"
                        " declared in ",
                        0),
            0u)
      << error;
  EXPECT_EQ(serialized_load_bytes(bomb, "m.serialized"), 0u);
}

TEST(SerializedLoader, LoadBytesCountEveryShapeFromItsHeader) {
  ShapeSpec a = quad(0);
  ShapeSpec b = quad(1);
  b.flags |= 0x3;  // normals and uvs
  b.normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  b.uvs = {0, 0, 1, 0, 1, 1, 0, 1};
  // a: 4 vertices x 24 + 2 triangles x 12; b: 4 x (24 + 24 + 16) + 2 x 12.
  EXPECT_EQ(serialized_load_bytes(file_bytes({a, b}), "m.serialized"), 120u + 280u);
  EXPECT_EQ(serialized_load_bytes(file_bytes({a}, 3), "m.serialized"), 120u);
  EXPECT_EQ(serialized_load_bytes("not a mesh", "m.serialized"), 0u);
  // A bad second dictionary entry: only the first shape can be loaded.
  std::string file = file_bytes({a, b});
  uint64_t wrong = 7;
  std::memcpy(file.data() + file.size() - 4 - 8, &wrong, 8);
  EXPECT_EQ(serialized_load_bytes(file, "m.serialized"), 120u);
}

TEST(SerializedLoader, BadDictionaryIsNamed) {
  std::string file = file_bytes({quad(0), quad(1)});
  // Point the second entry into the middle of the first shape.
  uint64_t wrong = 7;
  std::memcpy(file.data() + file.size() - 4 - 8, &wrong, 8);
  EXPECT_EQ(serialized_error(file, 1), "m.serialized: no shape header at offset 7 (bad shape dictionary)");
  uint32_t many = 1'000'000;
  std::memcpy(file.data() + file.size() - 4, &many, 4);
  EXPECT_EQ(serialized_error(file, 1),
            "m.serialized: shape dictionary of 1000000 shapes does not fit in the file");
}

TEST(SerializedLoader, MeshFileLoadsTheChosenShape) {
  std::string file = file_bytes({quad(0), quad(5)});
  MeshFileOptions options;
  options.shape_index = 1;
  std::vector<std::string> files_read;
  std::vector<MeshPart> parts = load_mesh_file(
      "meshes/two.serialized", testing::memory_reader({{"meshes/two.serialized", file}}), options,
      files_read);
  ASSERT_EQ(parts.size(), 1u);
  EXPECT_EQ(parts[0].mesh.positions[0].z, 5);
  EXPECT_EQ(files_read, std::vector<std::string>{"meshes/two.serialized"});
}

}  // namespace
}  // namespace tessera
