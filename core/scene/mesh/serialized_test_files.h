// Mitsuba serialized mesh files written field by field, for the tests of the serialized loader
// (mesh/serialized_loader_test.cpp) and of the native `mesh` shape that reads them
// (native/serialized_mesh_test.cpp).
#pragma once

#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace tessera::testing {

/// Little-endian bytes, appended value by value.
class Bytes {
 public:
  template <typename T>
  Bytes& put(T v) {
    unsigned char raw[sizeof(T)];
    std::memcpy(raw, &v, sizeof(T));  // the test machines are little-endian (x86-64)
    data.append(reinterpret_cast<const char*>(raw), sizeof(T));
    return *this;
  }
  Bytes& text(const std::string& s) {
    data += s;
    data += '\0';
    return *this;
  }
  std::string data;
};

/// One shape as the format stores it.
struct ShapeSpec {
  uint32_t flags = 0x1000;
  std::string name = "shape";
  std::vector<double> positions;  // 3 per vertex
  std::vector<double> normals;
  std::vector<double> uvs;
  std::vector<double> colors;
  std::vector<uint32_t> indices;  // 3 per triangle
};

inline std::string compress(const std::string& raw) {
  uLongf size = compressBound(raw.size());
  std::string out(size, '\0');
  EXPECT_EQ(compress2(reinterpret_cast<Bytef*>(out.data()), &size,
                      reinterpret_cast<const Bytef*>(raw.data()), raw.size(), 9),
            Z_OK);
  out.resize(size);
  return out;
}

inline std::string shape_bytes(const ShapeSpec& s, uint16_t version) {
  bool doubles = (s.flags & 0x2000) != 0;
  Bytes body;
  body.put<uint32_t>(s.flags);
  if (version == 4) body.text(s.name);
  body.put<uint64_t>(s.positions.size() / 3).put<uint64_t>(s.indices.size() / 3);
  for (const std::vector<double>* array : {&s.positions, &s.normals, &s.uvs, &s.colors}) {
    for (double v : *array) doubles ? body.put<double>(v) : body.put<float>(float(v));
  }
  for (uint32_t i : s.indices) body.put<uint32_t>(i);
  Bytes head;
  head.put<uint16_t>(0x041C).put<uint16_t>(version);
  return head.data + compress(body.data);
}

/// A whole file: the shapes one after the other, then the dictionary of offsets and the count.
inline std::string file_bytes(const std::vector<ShapeSpec>& shapes, uint16_t version = 4) {
  std::string file;
  std::vector<uint64_t> offsets;
  for (const ShapeSpec& s : shapes) {
    offsets.push_back(file.size());
    file += shape_bytes(s, version);
  }
  Bytes tail;
  for (uint64_t o : offsets) version == 4 ? tail.put<uint64_t>(o) : tail.put<uint32_t>(uint32_t(o));
  tail.put<uint32_t>(uint32_t(shapes.size()));
  return file + tail.data;
}

inline ShapeSpec quad(double z) {
  ShapeSpec s;
  s.positions = {0, 0, z, 1, 0, z, 1, 1, z, 0, 1, z};
  s.indices = {0, 1, 2, 0, 2, 3};
  return s;
}

}  // namespace tessera::testing
