#include "scene/mesh/serialized_loader.h"

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "scene/mesh/mesh_limits.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

constexpr uint16_t kMagic = 0x041C;
constexpr uint16_t kVersion3 = 3;
constexpr uint16_t kVersion4 = 4;
constexpr uint32_t kHasNormals = 0x0001;
constexpr uint32_t kHasUvs = 0x0002;
constexpr uint32_t kHasColors = 0x0008;
constexpr uint32_t kDoublePrecision = 0x2000;
/// Deflate expands at most about 1032:1; a shape that declares more data than its compressed
/// bytes could hold is refused before its arrays are allocated.
constexpr uint64_t kMaxInflateRatio = 1040;
constexpr size_t kMaxShapeName = 4096;

template <typename T>
T little_endian(const unsigned char* p) {
  uint64_t value = 0;
  for (size_t i = 0; i < sizeof(T); ++i) value |= uint64_t(p[i]) << (8 * i);
  return static_cast<T>(value);
}

/// Reads exactly the requested number of bytes from one zlib stream, or throws.
class ZlibReader {
 public:
  ZlibReader(std::string_view compressed, const std::string& name) : name_(name) {
    stream_.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(compressed.data()));
    stream_.avail_in = static_cast<uInt>(std::min<size_t>(compressed.size(), UINT32_MAX));
    if (inflateInit(&stream_) != Z_OK) throw SceneError(name_ + ": cannot start zlib");
  }
  ~ZlibReader() { inflateEnd(&stream_); }
  ZlibReader(const ZlibReader&) = delete;
  ZlibReader& operator=(const ZlibReader&) = delete;

  void read(void* out, size_t size, const char* what) {
    auto* dst = static_cast<Bytef*>(out);
    while (size > 0) {
      if (ended_) fail(what);
      uInt chunk = static_cast<uInt>(std::min<size_t>(size, 1u << 30));
      stream_.next_out = dst;
      stream_.avail_out = chunk;
      int status = inflate(&stream_, Z_NO_FLUSH);
      size_t produced = chunk - stream_.avail_out;
      dst += produced;
      size -= produced;
      if (status == Z_STREAM_END) {
        ended_ = true;
      } else if (status != Z_OK || (produced == 0 && stream_.avail_in == 0)) {
        if (status == Z_DATA_ERROR) {
          throw SceneError(name_ + ": corrupt compressed data while reading the " + what);
        }
        fail(what);
      }
    }
  }

  template <typename T>
  T value(const char* what) {
    unsigned char bytes[sizeof(T)];
    read(bytes, sizeof(T), what);
    return little_endian<T>(bytes);
  }

  void skip(uint64_t size, const char* what) {
    std::vector<unsigned char> scratch(1 << 16);
    while (size > 0) {
      size_t chunk = std::min<uint64_t>(size, scratch.size());
      read(scratch.data(), chunk, what);
      size -= chunk;
    }
  }

 private:
  [[noreturn]] void fail(const char* what) {
    throw SceneError(name_ + ": truncated: the compressed data ends in the " + what);
  }

  std::string name_;
  z_stream stream_{};
  bool ended_ = false;
};

/// The byte offset of shape `shape_index`, from the dictionary at the end of the file.
uint64_t shape_offset(std::string_view bytes, uint16_t version, int shape_index,
                      const std::string& name) {
  if (shape_index == 0) return 0;
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  if (bytes.size() < 8) throw SceneError(name + ": truncated: no shape dictionary at the end");
  uint32_t count = little_endian<uint32_t>(data + bytes.size() - 4);
  if (static_cast<uint64_t>(shape_index) >= count) {
    throw SceneError(name + ": shape_index " + std::to_string(shape_index) +
                     " out of range (the file holds " + std::to_string(count) + " shapes)");
  }
  uint64_t entry = version == kVersion4 ? 8 : 4;
  if (uint64_t(count) * entry + 4 > bytes.size()) {
    throw SceneError(name + ": shape dictionary of " + std::to_string(count) +
                     " shapes does not fit in the file");
  }
  uint64_t at = bytes.size() - 4 - entry * (count - static_cast<uint64_t>(shape_index));
  uint64_t offset = version == kVersion4 ? little_endian<uint64_t>(data + at)
                                         : little_endian<uint32_t>(data + at);
  if (offset > bytes.size() - 4) {
    throw SceneError(name + ": shape " + std::to_string(shape_index) + " at offset " +
                     std::to_string(offset) + " lies beyond the end of the file");
  }
  return offset;
}

void check_header(std::string_view bytes, uint64_t offset, const std::string& name,
                  uint16_t expected_version) {
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data()) + offset;
  uint16_t magic = little_endian<uint16_t>(data);
  uint16_t version = little_endian<uint16_t>(data + 2);
  if (magic != kMagic || version != expected_version) {
    throw SceneError(name + ": no shape header at offset " + std::to_string(offset) +
                     " (bad shape dictionary)");
  }
}

std::string read_shape_name(ZlibReader& in, const std::string& name) {
  std::string shape_name;
  for (;;) {
    char c = in.value<char>("shape name");
    if (c == 0) return shape_name;
    if (shape_name.size() == kMaxShapeName) {
      throw SceneError(name + ": shape name longer than " + std::to_string(kMaxShapeName) +
                       " bytes (corrupt file?)");
    }
    shape_name += c;
  }
}

/// Reads count * dim reals (float or double) into doubles.
std::vector<double> read_reals(ZlibReader& in, uint64_t count, bool doubles, const char* what) {
  std::vector<double> values(count);
  if (doubles) {
    std::vector<unsigned char> raw(count * 8);
    in.read(raw.data(), raw.size(), what);
    for (uint64_t i = 0; i < count; ++i) {
      uint64_t bits = little_endian<uint64_t>(raw.data() + 8 * i);
      std::memcpy(&values[i], &bits, 8);
    }
  } else {
    std::vector<unsigned char> raw(count * 4);
    in.read(raw.data(), raw.size(), what);
    for (uint64_t i = 0; i < count; ++i) {
      uint32_t bits = little_endian<uint32_t>(raw.data() + 4 * i);
      float f;
      std::memcpy(&f, &bits, 4);
      values[i] = f;
    }
  }
  return values;
}

void check_counts(uint64_t vertices, uint64_t triangles, uint64_t bytes_per_vertex,
                  uint64_t compressed, const std::string& name) {
  if (vertices > kMaxMeshElements) {
    throw SceneError(name + ": " + std::to_string(vertices) + " vertices (at most " +
                     std::to_string(kMaxMeshElements) + ")");
  }
  if (triangles > kMaxMeshElements) {
    throw SceneError(name + ": " + std::to_string(triangles) + " triangles (at most " +
                     std::to_string(kMaxMeshElements) + ")");
  }
  uint64_t declared = vertices * bytes_per_vertex + triangles * 12;
  if (declared > compressed * kMaxInflateRatio) {
    throw SceneError(name + ": truncated: " + std::to_string(vertices) + " vertices and " +
                     std::to_string(triangles) + " triangles cannot fit in " +
                     std::to_string(compressed) + " compressed bytes");
  }
}

void read_arrays(ZlibReader& in, uint32_t flags, uint64_t vertices, uint64_t triangles,
                 bool read_normals, const std::string& name, TriangleMesh& mesh) {
  bool doubles = (flags & kDoublePrecision) != 0;
  std::vector<double> p = read_reals(in, 3 * vertices, doubles, "vertex positions");
  mesh.positions.resize(vertices);
  for (uint64_t i = 0; i < vertices; ++i) {
    mesh.positions[i] = {p[3 * i], p[3 * i + 1], p[3 * i + 2]};
    if (!std::isfinite(p[3 * i]) || !std::isfinite(p[3 * i + 1]) || !std::isfinite(p[3 * i + 2])) {
      throw SceneError(name + ": vertex " + std::to_string(i) + ": position is not finite");
    }
  }
  if (flags & kHasNormals) {
    std::vector<double> n = read_reals(in, 3 * vertices, doubles, "vertex normals");
    if (read_normals) {
      mesh.normals.resize(vertices);
      for (uint64_t i = 0; i < vertices; ++i) {
        mesh.normals[i] = {n[3 * i], n[3 * i + 1], n[3 * i + 2]};
      }
    }
  }
  if (flags & kHasUvs) {
    std::vector<double> uv = read_reals(in, 2 * vertices, doubles, "texture coordinates");
    mesh.uvs.resize(vertices);
    for (uint64_t i = 0; i < vertices; ++i) {
      mesh.uvs[i] = {uv[2 * i], uv[2 * i + 1]};
      if (!std::isfinite(uv[2 * i]) || !std::isfinite(uv[2 * i + 1])) {
        throw SceneError(name + ": vertex " + std::to_string(i) +
                         ": texture coordinate is not finite");
      }
    }
  }
  if (flags & kHasColors) in.skip(3 * vertices * (doubles ? 8 : 4), "vertex colours");
  std::vector<unsigned char> raw(12 * triangles);
  in.read(raw.data(), raw.size(), "triangle indices");
  mesh.indices.resize(triangles);
  for (uint64_t t = 0; t < triangles; ++t) {
    for (int k = 0; k < 3; ++k) {
      uint32_t index = little_endian<uint32_t>(raw.data() + 12 * t + 4 * k);
      if (index >= vertices) {
        throw SceneError(name + ": triangle " + std::to_string(t) + ": vertex index " +
                         std::to_string(index) + " out of range (" + std::to_string(vertices) +
                         " vertices)");
      }
      mesh.indices[t][k] = index;
    }
  }
  if (!normals_usable(mesh)) mesh.normals.clear();
}

}  // namespace

SerializedMesh load_serialized_mesh(std::string_view bytes, const std::string& name,
                                    int shape_index, bool read_normals) {
  if (bytes.size() < 4) throw SceneError(name + ": truncated: no serialized file header");
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  uint16_t magic = little_endian<uint16_t>(data);
  uint16_t version = little_endian<uint16_t>(data + 2);
  if (magic != kMagic) {
    throw SceneError(name + ": not a Mitsuba serialized mesh (bad magic number)");
  }
  if (version != kVersion3 && version != kVersion4) {
    throw SceneError(name + ": unsupported serialized format version " + std::to_string(version) +
                     " (expected 3 or 4)");
  }
  if (shape_index < 0) {
    throw SceneError(name + ": shape_index must be >= 0 (got " + std::to_string(shape_index) + ")");
  }
  uint64_t offset = shape_offset(bytes, version, shape_index, name);
  check_header(bytes, offset, name, version);
  std::string_view compressed = bytes.substr(offset + 4);
  ZlibReader in(compressed, name);

  SerializedMesh out;
  uint32_t flags = in.value<uint32_t>("flags");
  if (version == kVersion4) out.shape_name = read_shape_name(in, name);
  uint64_t vertices = in.value<uint64_t>("vertex count");
  uint64_t triangles = in.value<uint64_t>("triangle count");
  uint64_t real = (flags & kDoublePrecision) ? 8 : 4;
  uint64_t per_vertex = real * (3 + ((flags & kHasNormals) ? 3 : 0) + ((flags & kHasUvs) ? 2 : 0) +
                                ((flags & kHasColors) ? 3 : 0));
  check_counts(vertices, triangles, per_vertex, compressed.size(), name);
  read_arrays(in, flags, vertices, triangles, read_normals, name, out.mesh);
  return out;
}

}  // namespace tessera
